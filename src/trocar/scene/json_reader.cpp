#include "trocar/scene/json_reader.h"

#include <cmath>
#include <cstdio>

#include "trocar/core/error.h"

namespace trocar {
namespace {

const char* type_name(const nlohmann::json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_null()) return "null";
  return "something else";
}

std::string number_text(Real x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", x);
  return text;
}

}  // namespace

void JsonReader::fail(const std::string& reason) const {
  throw Error(file_ + ": " + (path_.empty() ? std::string() : path_ + ": ") + reason);
}

void JsonReader::expect_type(bool ok, const char* what) const {
  if (!ok) fail(std::string("must be ") + what + ", not " + type_name(*value_));
}

void JsonReader::expect_keys(std::initializer_list<std::string_view> allowed) const {
  expect_type(value_->is_object(), "an object");
  for (const auto& item : value_->items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || item.key() == a;
    if (!known) {
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      at(item.key()).fail("unknown key (expected one of: " + list + ")");
    }
  }
}

bool JsonReader::has(std::string_view key) const {
  return value_->is_object() && value_->contains(key);
}

JsonReader JsonReader::at(std::string_view key) const {
  expect_type(value_->is_object(), "an object");
  const std::string child = path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  const auto it = value_->find(key);
  if (it == value_->end()) JsonReader(*value_, file_, child).fail("missing (required)");
  return JsonReader(*it, file_, child);
}

JsonReader JsonReader::at(std::size_t i) const {
  expect_type(value_->is_array(), "an array");
  return JsonReader((*value_)[i], file_, path_ + "[" + std::to_string(i) + "]");
}

std::size_t JsonReader::array_size() const {
  expect_type(value_->is_array(), "an array");
  return value_->size();
}

Real JsonReader::number() const {
  expect_type(value_->is_number(), "a number");
  const Real x = value_->get<Real>();
  if (!std::isfinite(x)) fail("must be finite");
  return x;
}

Real JsonReader::number_at_least(Real min) const {
  const Real x = number();
  if (x < min) fail("must be >= " + number_text(min));
  return x;
}

Real JsonReader::number_above(Real min) const {
  const Real x = number();
  if (!(x > min)) fail("must be > " + number_text(min));
  return x;
}

std::int64_t JsonReader::integer(std::int64_t min, std::int64_t max) const {
  expect_type(value_->is_number_integer(), "an integer");
  const std::int64_t x = value_->get<std::int64_t>();
  if (x < min || x > max)
    fail("must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], not " + std::to_string(x));
  return x;
}

bool JsonReader::boolean() const {
  expect_type(value_->is_boolean(), "a boolean");
  return value_->get<bool>();
}

std::string JsonReader::string() const {
  expect_type(value_->is_string(), "a string");
  return value_->get<std::string>();
}

Vec3 JsonReader::vec3() const {
  expect_type(value_->is_array() && value_->size() == 3, "an array of 3 numbers");
  return Vec3(at(std::size_t{0}).number(), at(std::size_t{1}).number(), at(std::size_t{2}).number());
}

}  // namespace trocar
