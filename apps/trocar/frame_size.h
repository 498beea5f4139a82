#pragma once
// "WIDTHxHEIGHT" options (`run --size`, `view --size`).
#include <stdexcept>
#include <string>

#include "trocar/core/error.h"

namespace trocar::cli {

/// Parses "WxH" into width and height (each 16…8192 pixels); throws trocar::Error naming `option`.
inline void parse_frame_size(const std::string& text, const char* option, int& width, int& height) {
  const auto x = text.find('x');
  try {
    if (x == std::string::npos) throw std::invalid_argument(text);
    std::size_t used = 0;
    width = std::stoi(text.substr(0, x), &used);
    if (used != x) throw std::invalid_argument(text);
    height = std::stoi(text.substr(x + 1), &used);
    if (used != text.size() - x - 1) throw std::invalid_argument(text);
  } catch (const std::logic_error&) {
    throw Error(std::string(option) + ": \"" + text + "\" is not WIDTHxHEIGHT (e.g. 1280x720)");
  }
  if (width < 16 || height < 16 || width > 8192 || height > 8192)
    throw Error(std::string(option) + ": " + text + ": each side must be 16 to 8192 pixels");
}

}  // namespace trocar::cli
