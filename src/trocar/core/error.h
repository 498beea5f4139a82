#pragma once
/// Errors at the edges of the library (files, scenes, arguments), with the place they come from.
#include <cstdint>
#include <stdexcept>
#include <string>

namespace trocar {

/// Base of every error trocar throws; `what()` is a complete, user-facing sentence.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Where in a file an error was found: a 1-based line for text, or a byte offset for binary.
struct FileLocation {
  enum class Kind { kNone, kLine, kByte };
  Kind kind = Kind::kNone;  ///< which of the fields below is meaningful
  std::uint64_t value = 0;  ///< the line (1-based) or the byte offset (0-based)

  static FileLocation line(std::uint64_t l) { return {Kind::kLine, l}; }
  static FileLocation byte(std::uint64_t b) { return {Kind::kByte, b}; }
  static FileLocation none() { return {}; }
};

/// A malformed or unreadable file. The message reads "FILE:LINE: reason",
/// "FILE: byte N: reason" or "FILE: reason".
class FileError : public Error {
 public:
  FileError(std::string file, FileLocation where, std::string reason);

  const std::string& file() const { return file_; }        ///< the path as given
  const FileLocation& where() const { return where_; }     ///< line or byte offset
  const std::string& reason() const { return reason_; }    ///< the reason alone

 private:
  std::string file_;
  FileLocation where_;
  std::string reason_;
};

}  // namespace trocar
