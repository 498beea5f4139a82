#pragma once
/// Validating reader over a JSON value: every access knows the file and the key path, and every
/// error is a trocar::Error "FILE: PATH: reason" (e.g. "scene.json: tissues[0].material.k_area:
/// must be >= 0").
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "trocar/core/types.h"

namespace trocar {

/// A JSON value with its file and key path. Cheap to copy (holds a pointer to the value).
class JsonReader {
 public:
  /// The root of `file`'s document.
  JsonReader(const nlohmann::json& value, std::string file, std::string path = "")
      : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

  const nlohmann::json& value() const { return *value_; }  ///< the JSON value
  const std::string& file() const { return file_; }        ///< the file name used in errors
  const std::string& path() const { return path_; }        ///< key path ("" for the root)

  /// Throws trocar::Error "FILE: PATH: reason" (or "FILE: reason" at the root).
  [[noreturn]] void fail(const std::string& reason) const;

  /// Requires an object whose keys are all in `allowed`; an unknown key fails naming it.
  void expect_keys(std::initializer_list<std::string_view> allowed) const;
  /// True when this is an object with `key`.
  bool has(std::string_view key) const;
  /// The member `key` (fails when absent).
  JsonReader at(std::string_view key) const;
  /// Element i of an array.
  JsonReader at(std::size_t i) const;
  /// The array's size (fails when not an array).
  std::size_t array_size() const;

  bool is_object() const { return value_->is_object(); }   ///< JSON object
  bool is_string() const { return value_->is_string(); }   ///< JSON string
  bool is_number() const { return value_->is_number(); }   ///< JSON number
  bool is_null() const { return value_->is_null(); }       ///< JSON null

  /// A number (fails on another type or a non-finite value).
  Real number() const;
  /// A number ≥ min.
  Real number_at_least(Real min) const;
  /// A number > min.
  Real number_above(Real min) const;
  /// An integer in [min, max].
  std::int64_t integer(std::int64_t min, std::int64_t max) const;
  /// A boolean.
  bool boolean() const;
  /// A string.
  std::string string() const;
  /// An array of three numbers.
  Vec3 vec3() const;

  /// Optional members with a default.
  Real number_or(std::string_view key, Real fallback) const { return has(key) ? at(key).number() : fallback; }
  bool boolean_or(std::string_view key, bool fallback) const { return has(key) ? at(key).boolean() : fallback; }
  Vec3 vec3_or(std::string_view key, const Vec3& fallback) const { return has(key) ? at(key).vec3() : fallback; }
  std::string string_or(std::string_view key, const std::string& fallback) const {
    return has(key) ? at(key).string() : fallback;
  }

 private:
  void expect_type(bool ok, const char* what) const;
  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

}  // namespace trocar
