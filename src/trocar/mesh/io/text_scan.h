#pragma once
/// Small building blocks for the text mesh readers (OBJ, ASCII STL, and any other text format):
/// a line scanner and a token scanner that track 1-based line numbers, a splitter for the tokens
/// of one line, number parsing with std::from_chars (no locale, no iostreams), and helpers for
/// error messages. Nothing here throws or allocates except quote(); the readers turn the status
/// values into FileError with the file name and line.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace trocar::text {

/// Blank bytes that separate tokens inside a line: space, \t, \r, \v, \f (not \n).
constexpr bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Whitespace including the line feed.
constexpr bool is_space(char c) { return c == '\n' || is_blank(c); }

/// Offset of the first byte that does not belong in a text file: a control byte (< 0x20, or
/// 0x7F) other than \t \n \v \f \r. Returns std::string_view::npos when there is none. Bytes
/// ≥ 0x80 are allowed (UTF-8 names and comments).
std::size_t find_binary_byte(std::string_view s);

/// A printable rendering of a token for error messages: 'abc' in single quotes, bytes outside
/// printable ASCII written as \xNN, cut after 40 bytes with "..." appended.
std::string quote(std::string_view token);

/// Case-insensitive (ASCII) equality, for keywords such as STL's "solid" / "SOLID".
bool iequals(std::string_view a, std::string_view b);

/// True when s starts with prefix, ignoring ASCII case.
bool istarts_with(std::string_view s, std::string_view prefix);

/// Iterates over the lines of a text. LF and CR LF both end a line (the terminator is not part
/// of the line); a last line without a terminator is still returned; a UTF-8 byte-order mark at
/// the very beginning is skipped.
class LineScanner {
 public:
  /// Scans `text`, which must outlive the scanner.
  explicit LineScanner(std::string_view text);

  /// Puts the next line in `line` and returns true, or returns false at the end of the text.
  bool next(std::string_view& line);
  /// 1-based number of the line last returned by next() (0 before the first call).
  std::uint64_t line_number() const { return line_number_; }
  /// Byte offset of the start of the line last returned by next().
  std::size_t line_offset() const { return line_offset_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_offset_ = 0;
  std::uint64_t line_number_ = 0;
};

/// Splits one line (or any string without meaningful newlines) into blank-separated tokens.
class Tokens {
 public:
  /// Splits `s`, which must outlive the splitter.
  explicit Tokens(std::string_view s) : s_(s) {}

  /// Puts the next token in `token` and returns true, or returns false when none is left.
  bool next(std::string_view& token);
  /// What is left after the tokens taken so far, without leading or trailing blanks.
  std::string_view rest() const;

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
};

/// A stream of whitespace-separated tokens across lines, for free-form formats (ASCII STL,
/// VRML, legacy VTK). Tracks the 1-based line of each token. Optionally treats everything from
/// a comment character to the end of its line as whitespace.
class TokenScanner {
 public:
  /// Scans `text` (which must outlive the scanner); `comment` is the comment character, or
  /// '\0' for none. A UTF-8 byte-order mark at the beginning is skipped.
  explicit TokenScanner(std::string_view text, char comment = '\0');

  /// Puts the next token in `token` and returns true, or returns false at the end of the text.
  bool next(std::string_view& token);
  /// Line (1-based) of the token last returned by next(); after next() returned false, the
  /// last line of the text.
  std::uint64_t line() const { return token_line_; }
  /// Byte offset of the token last returned by next().
  std::size_t offset() const { return token_offset_; }
  /// Returns the rest of the current line (the line of the last token), without the leading
  /// and trailing blanks, and moves past it; the next token comes from a later line.
  std::string_view rest_of_line();
  /// True when no token is left.
  bool at_end();

 private:
  void skip_space();

  std::string_view text_;
  char comment_;
  std::size_t pos_ = 0;
  std::uint64_t line_ = 1;  // line at pos_
  std::uint64_t token_line_ = 1;
  std::size_t token_offset_ = 0;
};

/// The outcome of parsing a number token.
enum class NumberStatus {
  kOk,          ///< the whole token is a finite number
  kInvalid,     ///< not a number, or trailing characters
  kOutOfRange,  ///< too large in magnitude for the type
  kNotFinite,   ///< "nan", "inf", "infinity" (any case, any sign)
};

/// Parses the whole token as a double: optional sign ('+' or '-'), decimal digits with an
/// optional point and exponent (what std::from_chars' general format accepts). A value too
/// small for a double (e.g. 1e-400) gives ±0 and kOk; too large gives kOutOfRange; NaN and
/// infinities give kNotFinite (out is then set to that value).
NumberStatus parse_real(std::string_view token, double& out);

/// Parses the whole token as a signed 64-bit decimal integer with an optional sign.
NumberStatus parse_int(std::string_view token, std::int64_t& out);

/// A short phrase for a failed status, to follow a quoted token: "is not a number",
/// "is out of range", "is not finite" ("is a number" for kOk).
const char* describe(NumberStatus status);

}  // namespace trocar::text
