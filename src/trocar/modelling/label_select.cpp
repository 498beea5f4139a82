#include "trocar/modelling/label_select.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "trocar/core/error.h"

namespace trocar {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool is_integer(const std::string& s) {
  if (s.empty()) return false;
  std::size_t start = s[0] == '-' ? 1 : 0;
  return start < s.size() && std::all_of(s.begin() + static_cast<std::ptrdiff_t>(start), s.end(),
                                         [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

std::string present_list(const std::map<int, std::size_t>& counts) {
  std::string out;
  std::size_t shown = 0;
  for (const auto& [value, n] : counts) {
    if (shown++ == 40) {
      out += ", ...";
      break;
    }
    out += (out.empty() ? "" : ", ") + std::to_string(value);
  }
  return out.empty() ? "none" : out;
}

[[noreturn]] void fail(const Volume& v, const std::string& reason) { throw FileError(v.source, FileLocation::none(), reason); }

}  // namespace

std::map<int, std::size_t> label_counts(const Volume& volume, int layer) {
  std::map<int, std::size_t> counts;
  for (float x : volume.layers.at(static_cast<std::size_t>(layer))) {
    if (x != 0 && x == std::floor(x) && std::abs(x) < 1e9f) ++counts[static_cast<int>(x)];
  }
  return counts;
}

Mask select_mask(const Volume& volume, const LabelQuery& query) {
  Mask mask;
  mask.inside.assign(volume.voxel_count(), 0);
  int layer = std::max(query.layer, 0);
  if (query.layer >= static_cast<int>(volume.layers.size())) {
    fail(volume, "layer " + std::to_string(query.layer) + " asked for, the volume has " +
                     std::to_string(volume.layers.size()));
  }
  if (query.label.empty()) {
    const Real lo = query.threshold_low.value_or(-std::numeric_limits<Real>::infinity());
    const Real hi = query.threshold_high.value_or(std::numeric_limits<Real>::infinity());
    if (!query.threshold_low && !query.threshold_high) fail(volume, "neither a label nor a threshold was given");
    const std::vector<float>& values = volume.layers[static_cast<std::size_t>(layer)];
    for (std::size_t p = 0; p < values.size(); ++p) {
      mask.inside[p] = values[p] >= lo && values[p] <= hi ? 1 : 0;
      mask.count += mask.inside[p];
    }
    std::ostringstream what;
    what << "values in [" << lo << ", " << hi << "]";
    mask.what = what.str();
    if (mask.count == 0) fail(volume, "no voxel has a value in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return mask;
  }

  // By value, or by name: the file's own names first, then the class map.
  int value = 0;
  if (is_integer(query.label)) {
    value = std::stoi(query.label);
    const auto named = volume.names.find({layer, value});
    if (named != volume.names.end()) mask.name = named->second;
    else if (query.class_map.count(value) != 0) mask.name = query.class_map.at(value);
  } else {
    const std::string want = lower(query.label);
    bool found = false;
    for (const auto& [key, name] : volume.names) {
      if (lower(name) == want && (query.layer < 0 || key.first == query.layer)) {
        layer = key.first;
        value = key.second;
        found = true;
        break;
      }
    }
    for (auto it = query.class_map.begin(); !found && it != query.class_map.end(); ++it) {
      if (lower(it->second) == want) {
        value = it->first;
        found = true;
      }
    }
    if (!found) {
      std::string names;
      for (const auto& [key, name] : volume.names) names += (names.empty() ? "" : ", ") + name;
      for (const auto& [key, name] : query.class_map) names += (names.empty() ? "" : ", ") + name;
      fail(volume, "no segment is named \"" + query.label + "\" (" +
                       (names.empty() ? std::string("the file names no segments; give a label value or a class map")
                                      : "names: " + names) + ")");
    }
    mask.name = query.label;
  }
  if (layer >= static_cast<int>(volume.layers.size())) fail(volume, "segment layer " + std::to_string(layer) + " is not in the file");
  const std::vector<float>& values = volume.layers[static_cast<std::size_t>(layer)];
  const auto v = static_cast<float>(value);
  for (std::size_t p = 0; p < values.size(); ++p) {
    mask.inside[p] = values[p] == v ? 1 : 0;
    mask.count += mask.inside[p];
  }
  mask.label = value;
  mask.what = "label " + std::to_string(value) + (mask.name.empty() ? "" : " (" + mask.name + ")");
  if (mask.count == 0) {
    fail(volume, mask.what + " is not in the volume (labels present: " + present_list(label_counts(volume, layer)) + ")");
  }
  return mask;
}

std::map<int, std::string> read_class_map(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw FileError(file, FileLocation::none(), "cannot open the class map");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::map<int, std::string> out;
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{') {
    try {
      const nlohmann::json j = nlohmann::json::parse(text);
      for (const auto& [key, name] : j.items()) {
        if (!is_integer(key) || !name.is_string()) throw FileError(file, FileLocation::none(), "key \"" + key + "\": expected \"N\": \"name\"");
        out[std::stoi(key)] = name.get<std::string>();
      }
      return out;
    } catch (const nlohmann::json::exception&) {
      // Not JSON after all (a Python dict body): read it line by line below.
    }
  }
  static const std::regex line_re(R"re(^\s*["']?(-?\d+)["']?\s*[:=,]?\s*["']?([A-Za-z0-9_ .()+-]*[A-Za-z0-9_)])["']?\s*,?\s*$)re");
  std::istringstream lines(text);
  std::string line;
  std::uint64_t number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto hash = line.find('#');
    const std::string body = hash == std::string::npos ? line : line.substr(0, hash);
    if (body.find_first_not_of(" \t{}") == std::string::npos) continue;
    std::smatch m;
    if (!std::regex_match(body, m, line_re)) {
      throw FileError(file, FileLocation::line(number), "expected \"VALUE NAME\" (e.g. 5 liver)");
    }
    out[std::stoi(m[1].str())] = m[2].str();
  }
  if (out.empty()) throw FileError(file, FileLocation::none(), "the class map names no labels");
  return out;
}

}  // namespace trocar
