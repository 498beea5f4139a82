#include "trocar/core/error.h"

namespace trocar {
namespace {

std::string format_file_error(const std::string& file, const FileLocation& where,
                              const std::string& reason) {
  switch (where.kind) {
    case FileLocation::Kind::kLine:
      return file + ":" + std::to_string(where.value) + ": " + reason;
    case FileLocation::Kind::kByte:
      return file + ": byte " + std::to_string(where.value) + ": " + reason;
    case FileLocation::Kind::kNone:
      break;
  }
  return file + ": " + reason;
}

}  // namespace

FileError::FileError(std::string file, FileLocation where, std::string reason)
    : Error(format_file_error(file, where, reason)),
      file_(std::move(file)),
      where_(where),
      reason_(std::move(reason)) {}

}  // namespace trocar
