#pragma once
/// Tokenizer for VRML97 (ISO/IEC 14772-1) text, used only by the VRML reader.
#include <cstdint>
#include <string>
#include <string_view>

#include "trocar/core/error.h"

namespace trocar::vrml {

/// What a token is. Words are maximal runs of characters that are not whitespace, commas or
/// one of `# " { } [ ]`: node types, field names, DEF names, numbers, TRUE/FALSE, `a.b`.
enum class TokenKind { kWord, kString, kOpenBrace, kCloseBrace, kOpenBracket, kCloseBracket, kEnd };

/// One token and the 1-based line it starts on.
struct Token {
  TokenKind kind = TokenKind::kEnd;
  std::string_view text;   ///< the word, or a string's raw content without quotes (escapes kept)
  std::uint64_t line = 1;  ///< line of the first character
};

/// Splits VRML text into tokens with up to two tokens of look-ahead. Comments (`#` to end of
/// line) and commas are whitespace. The constructor checks the `#VRML V2.0 utf8` header.
class Lexer {
 public:
  /// `name` is the file name used in errors; it must outlive the lexer.
  Lexer(std::string_view bytes, const std::string& name);

  /// The token `ahead` places ahead (0 = the next one, at most 1).
  const Token& peek(std::size_t ahead = 0);
  /// Consumes and returns the next token.
  Token next();
  /// A FileError at the given line.
  FileError error(std::uint64_t line, const std::string& reason) const;

 private:
  Token scan();

  std::string_view bytes_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::uint64_t line_ = 1;
  Token buffer_[2];
  std::size_t buffered_ = 0;
};

/// "'text'" for error messages, shortened to 40 characters.
std::string quote(std::string_view text);

}  // namespace trocar::vrml
