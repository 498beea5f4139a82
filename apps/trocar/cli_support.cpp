#include "cli_support.h"

#include <fstream>

#include "trocar/core/error.h"

namespace trocar::cli {

void apply_method_option(Scene& scene, const std::string& method) {
  if (method.empty()) return;
  const auto parsed = parse_response_method(method);
  if (!parsed) throw Error("--method: unknown method \"" + method + "\" (known: sdf, obb, primitive, normal, project)");
  scene.settings.response.method = *parsed;
}

void write_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw Error(path.string() + ": cannot write");
    out << text;
    if (!out) throw Error(path.string() + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace trocar::cli
