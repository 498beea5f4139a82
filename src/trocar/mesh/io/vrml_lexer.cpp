#include "trocar/mesh/io/vrml_lexer.h"

namespace trocar::vrml {
namespace {

constexpr std::string_view kHeader = "#VRML V2.0 utf8";

bool is_separator(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u <= 0x20 || c == ',' || u == 0x7f;  // whitespace, control characters, commas
}

bool ends_word(char c) {
  return is_separator(c) || c == '#' || c == '"' || c == '{' || c == '}' || c == '[' || c == ']';
}

}  // namespace

Lexer::Lexer(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {
  if (bytes_.substr(0, kHeader.size()) != kHeader)
    throw error(1, "missing '#VRML V2.0 utf8' header (only VRML97 is supported)");
}

FileError Lexer::error(std::uint64_t line, const std::string& reason) const {
  return FileError(name_, FileLocation::line(line), reason);
}

const Token& Lexer::peek(std::size_t ahead) {
  while (buffered_ <= ahead) buffer_[buffered_++] = scan();
  return buffer_[ahead];
}

Token Lexer::next() {
  if (buffered_ == 0) return scan();
  const Token t = buffer_[0];
  buffer_[0] = buffer_[1];
  --buffered_;
  return t;
}

Token Lexer::scan() {
  for (;;) {  // skip whitespace and comments
    if (pos_ >= bytes_.size()) return Token{TokenKind::kEnd, {}, line_};
    const char c = bytes_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (c == '#') {
      while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
    } else if (is_separator(c)) {
      ++pos_;
    } else {
      break;
    }
  }
  const char c = bytes_[pos_];
  const std::uint64_t line = line_;
  switch (c) {
    case '{': ++pos_; return Token{TokenKind::kOpenBrace, bytes_.substr(pos_ - 1, 1), line};
    case '}': ++pos_; return Token{TokenKind::kCloseBrace, bytes_.substr(pos_ - 1, 1), line};
    case '[': ++pos_; return Token{TokenKind::kOpenBracket, bytes_.substr(pos_ - 1, 1), line};
    case ']': ++pos_; return Token{TokenKind::kCloseBracket, bytes_.substr(pos_ - 1, 1), line};
    default: break;
  }
  if (c == '"') {
    const std::size_t start = ++pos_;
    while (pos_ < bytes_.size() && bytes_[pos_] != '"') {
      if (bytes_[pos_] == '\\' && pos_ + 1 < bytes_.size()) ++pos_;  // \" and \\ escapes
      if (bytes_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= bytes_.size()) throw error(line, "unterminated string");
    ++pos_;
    return Token{TokenKind::kString, bytes_.substr(start, pos_ - 1 - start), line};
  }
  const std::size_t start = pos_;
  while (pos_ < bytes_.size() && !ends_word(bytes_[pos_])) ++pos_;
  return Token{TokenKind::kWord, bytes_.substr(start, pos_ - start), line};
}

std::string quote(std::string_view text) {
  if (text.size() > 40) return "'" + std::string(text.substr(0, 40)) + "...'";
  return "'" + std::string(text) + "'";
}

}  // namespace trocar::vrml
