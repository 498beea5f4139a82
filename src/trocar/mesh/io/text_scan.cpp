#include "trocar/mesh/io/text_scan.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace trocar::text {
namespace {

constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

constexpr char to_lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

constexpr bool is_digit(char c) { return c >= '0' && c <= '9'; }

std::string_view skip_bom(std::string_view text) {
  return text.substr(0, 3) == kByteOrderMark ? text.substr(3) : text;
}

// from_chars reports result_out_of_range for both overflow and underflow. Tells them apart by
// the decimal exponent of the first significant digit: negative means the value is tiny.
// `s` has already been accepted by from_chars up to its end (no sign, digits, '.', exponent).
bool is_underflow(std::string_view s) {
  std::size_t i = 0;
  std::int64_t magnitude = 0;
  bool found = false;
  std::int64_t int_digits = 0;
  while (i < s.size() && is_digit(s[i])) {
    if (found || s[i] != '0') {
      found = true;
      ++int_digits;
    }
    ++i;
  }
  if (found) {
    magnitude = int_digits - 1;
  } else {
    if (i < s.size() && s[i] == '.') ++i;
    std::int64_t zeros = 0;
    while (i < s.size() && s[i] == '0') {
      ++zeros;
      ++i;
    }
    magnitude = -(zeros + 1);
  }
  while (i < s.size() && s[i] != 'e' && s[i] != 'E') ++i;
  if (i == s.size()) return magnitude < 0;
  std::string_view exponent = s.substr(i + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) exponent.remove_prefix(1);
  std::int64_t e = 0;
  const auto [ptr, ec] = std::from_chars(exponent.data(), exponent.data() + exponent.size(), e);
  if (ec != std::errc() || ptr != exponent.data() + exponent.size()) return negative;
  // |e| fits in int64 and |magnitude| is at most the token length, so this cannot overflow
  // unless e is within a token length of INT64_MAX; saturate in that case.
  if (e > INT64_MAX / 2) return negative;
  return (negative ? magnitude - e : magnitude + e) < 0;
}

}  // namespace

std::size_t find_binary_byte(std::string_view s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\v' && c != '\f' && c != '\r') || c == 0x7F)
      return i;
  }
  return std::string_view::npos;
}

std::string quote(std::string_view token) {
  constexpr std::size_t kMax = 40;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xF];
    }
  }
  out += '\'';
  if (token.size() > kMax) out += "...";
  return out;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (to_lower(a[i]) != to_lower(b[i])) return false;
  return true;
}

bool istarts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

// ---- LineScanner ----

LineScanner::LineScanner(std::string_view text) : text_(text) {
  if (skip_bom(text).size() != text.size()) pos_ = kByteOrderMark.size();
}

bool LineScanner::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  std::size_t len = stop - pos_;
  if (len > 0 && text_[pos_ + len - 1] == '\r') --len;
  line = text_.substr(pos_, len);
  line_offset_ = pos_;
  ++line_number_;
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  return true;
}

// ---- Tokens ----

bool Tokens::next(std::string_view& token) {
  while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
  if (pos_ >= s_.size()) return false;
  const std::size_t start = pos_;
  while (pos_ < s_.size() && !is_space(s_[pos_])) ++pos_;
  token = s_.substr(start, pos_ - start);
  return true;
}

std::string_view Tokens::rest() const {
  std::size_t b = pos_;
  std::size_t e = s_.size();
  while (b < e && is_space(s_[b])) ++b;
  while (e > b && is_space(s_[e - 1])) --e;
  return s_.substr(b, e - b);
}

// ---- TokenScanner ----

TokenScanner::TokenScanner(std::string_view text, char comment) : text_(text), comment_(comment) {
  if (skip_bom(text).size() != text.size()) pos_ = kByteOrderMark.size();
}

void TokenScanner::skip_space() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (is_blank(c)) {
      ++pos_;
    } else if (comment_ != '\0' && c == comment_) {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else {
      break;
    }
  }
}

bool TokenScanner::next(std::string_view& token) {
  skip_space();
  if (pos_ >= text_.size()) {
    token_line_ = line_;
    token_offset_ = pos_;
    return false;
  }
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !is_space(text_[pos_]) &&
         !(comment_ != '\0' && text_[pos_] == comment_))
    ++pos_;
  token = text_.substr(start, pos_ - start);
  token_line_ = line_;
  token_offset_ = start;
  return true;
}

std::string_view TokenScanner::rest_of_line() {
  // pos_ is on the last token's line unless a newline was already consumed after it, which
  // next() never does (it stops at the end of the token).
  std::size_t b = pos_;
  std::size_t e = text_.find('\n', pos_);
  if (e == std::string_view::npos) e = text_.size();
  pos_ = e;  // the newline itself is consumed (and counted) by the next skip_space()
  if (comment_ != '\0') {
    const std::size_t c = text_.substr(b, e - b).find(comment_);
    if (c != std::string_view::npos) e = b + c;
  }
  while (b < e && is_blank(text_[b])) ++b;
  while (e > b && is_blank(text_[e - 1])) --e;
  return text_.substr(b, e - b);
}

bool TokenScanner::at_end() {
  skip_space();
  return pos_ >= text_.size();
}

// ---- numbers ----

NumberStatus parse_real(std::string_view token, double& out) {
  std::string_view s = token;
  bool negative = false;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    negative = s[0] == '-';
    s.remove_prefix(1);
  }
  if (s.empty() || s[0] == '+' || s[0] == '-') return NumberStatus::kInvalid;
  double value = 0;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, value, std::chars_format::general);
  if (ptr != end) return NumberStatus::kInvalid;
  if (ec == std::errc::result_out_of_range) {
    if (!is_underflow(s)) return NumberStatus::kOutOfRange;
    value = 0.0;
  } else if (ec != std::errc()) {
    return NumberStatus::kInvalid;
  }
  out = negative ? -value : value;
  return std::isfinite(value) ? NumberStatus::kOk : NumberStatus::kNotFinite;
}

NumberStatus parse_int(std::string_view token, std::int64_t& out) {
  std::string_view s = token;
  if (!s.empty() && s[0] == '+') {
    s.remove_prefix(1);
    if (s.empty() || s[0] == '-') return NumberStatus::kInvalid;
  }
  if (s.empty()) return NumberStatus::kInvalid;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  if (ptr != end) return NumberStatus::kInvalid;
  if (ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (ec != std::errc()) return NumberStatus::kInvalid;
  return NumberStatus::kOk;
}

const char* describe(NumberStatus status) {
  switch (status) {
    case NumberStatus::kOk: return "is a number";
    case NumberStatus::kInvalid: return "is not a number";
    case NumberStatus::kOutOfRange: return "is out of range";
    case NumberStatus::kNotFinite: return "is not finite";
  }
  return "is not a number";
}

}  // namespace trocar::text
