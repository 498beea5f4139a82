#include "trocar/modelling/build_cache.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <vector>

#include <vtksys/MD5.h>

#include "trocar/core/error.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/modelling/organ_builder.h"
#include "trocar/scene/mesh_source.h"

namespace trocar {
namespace {

/// Bumped whenever the pipeline's output for the same input changes, so old cache entries
/// are not reused.
constexpr const char* kPipelineVersion = "trocar-organ-1";

std::atomic<unsigned> staging_counter{0};

std::string md5_hex(const std::vector<std::string>& parts) {
  vtksysMD5* md5 = vtksysMD5_New();
  vtksysMD5_Initialize(md5);
  for (const std::string& part : parts) {
    for (std::size_t at = 0; at < part.size(); at += 1 << 20) {
      const std::size_t n = std::min<std::size_t>(1 << 20, part.size() - at);
      vtksysMD5_Append(md5, reinterpret_cast<const unsigned char*>(part.data() + at), static_cast<int>(n));
    }
    vtksysMD5_Append(md5, reinterpret_cast<const unsigned char*>("\0"), 1);
  }
  char hex[33] = {};
  vtksysMD5_FinalizeHex(md5, hex);
  vtksysMD5_Delete(md5);
  return hex;
}

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string(), FileLocation::none(), "cannot open the file");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::filesystem::path existing_file(const JsonReader& key, const std::filesystem::path& scene_dir) {
  const std::filesystem::path path = scene_dir / key.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) key.fail("file not found: " + path.string());
  return path;
}

}  // namespace

std::filesystem::path cache_dir() {
  if (const char* dir = std::getenv("TROCAR_CACHE_DIR"); dir != nullptr && *dir != '\0') return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') return std::filesystem::path(xdg) / "trocar";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') return std::filesystem::path(home) / ".cache" / "trocar";
  return std::filesystem::temp_directory_path() / "trocar-cache";
}

TriMesh build_scene_mesh(const JsonReader& spec, const std::filesystem::path& scene_dir) {
  spec.expect_keys({"build", "label", "threshold", "class_map", "layer", "target_triangles", "smooth_iterations",
                    "presmooth_mm", "close_mm", "remesh_iterations", "all_components", "centre"});
  const std::filesystem::path volume_path = existing_file(spec.at("build"), scene_dir);
  OrganBuildOptions options;
  options.measure_distance = false;
  std::string class_map_bytes;
  if (spec.has("label")) {
    const JsonReader label = spec.at("label");
    options.query.label = label.is_string() ? label.string() : std::to_string(label.integer(-(1 << 30), 1 << 30));
  } else if (spec.has("threshold")) {
    const JsonReader t = spec.at("threshold");
    if (t.array_size() != 2) t.fail("expected [low, high] (null for an open end)");
    if (!t.at(std::size_t{0}).is_null()) options.query.threshold_low = t.at(std::size_t{0}).number();
    if (!t.at(std::size_t{1}).is_null()) options.query.threshold_high = t.at(std::size_t{1}).number();
  } else {
    spec.fail("a built mesh needs \"label\" (value or name) or \"threshold\" [low, high]");
  }
  if (spec.has("class_map")) {
    const std::filesystem::path map = existing_file(spec.at("class_map"), scene_dir);
    try {
      options.query.class_map = read_class_map(map);
      class_map_bytes = read_bytes(map);
    } catch (const Error& e) {
      spec.at("class_map").fail(e.what());
    }
  }
  if (spec.has("layer")) options.query.layer = static_cast<int>(spec.at("layer").integer(0, 1000));
  if (spec.has("target_triangles")) options.surface.target_triangles = static_cast<std::size_t>(spec.at("target_triangles").integer(0, 10'000'000));
  if (spec.has("smooth_iterations")) options.surface.smooth_iterations = static_cast<int>(spec.at("smooth_iterations").integer(0, 1000));
  if (spec.has("remesh_iterations")) options.surface.remesh_iterations = static_cast<int>(spec.at("remesh_iterations").integer(0, 50));
  if (spec.has("close_mm")) options.surface.close_radius = spec.at("close_mm").number_at_least(0) * 1e-3;
  if (spec.has("presmooth_mm")) options.surface.presmooth_sigma = spec.at("presmooth_mm").number_at_least(0) * 1e-3;
  options.surface.largest_component_only = !spec.boolean_or("all_components", false);

  std::string volume_bytes;
  try {
    volume_bytes = read_bytes(volume_path);
  } catch (const Error& e) {
    spec.at("build").fail(e.what());
  }
  const std::string key_text = std::string(kPipelineVersion) + " label=" + options.query.label +
                               " lo=" + (options.query.threshold_low ? std::to_string(*options.query.threshold_low) : "-") +
                               " hi=" + (options.query.threshold_high ? std::to_string(*options.query.threshold_high) : "-") +
                               " layer=" + std::to_string(options.query.layer) +
                               " tris=" + std::to_string(options.surface.target_triangles) +
                               " smooth=" + std::to_string(options.surface.smooth_iterations) +
                               " sigma=" + std::to_string(options.surface.presmooth_sigma) +
                               " remesh=" + std::to_string(options.surface.remesh_iterations) +
                               " close=" + std::to_string(options.surface.close_radius) +
                               " largest=" + std::to_string(options.surface.largest_component_only);
  const std::string key = md5_hex({volume_bytes, class_map_bytes, key_text});
  const std::filesystem::path cached = cache_dir() / "organs" / (key + ".obj");

  TriMesh mesh;
  std::error_code ec;
  if (std::filesystem::is_regular_file(cached, ec)) {
    try {
      mesh = load_mesh(cached);
    } catch (const Error&) {
      mesh = TriMesh{};  // a damaged cache entry is rebuilt
    }
  }
  if (mesh.empty()) {
    try {
      const Volume volume = read_volume(volume_path);
      const OrganBuild build = build_organ(volume, options);
      // Written into a private folder with the final names (the OBJ names its MTL, the MTL its
      // PNG), then renamed into place, the OBJ last: a concurrent reader sees a whole entry or
      // none. Caching is best effort: an unwritable cache costs a rebuild next time, not the scene.
      const std::filesystem::path staging =
          cached.parent_path() / (key + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(++staging_counter));
      try {
        std::filesystem::create_directories(staging);
        write_organ(build, staging / cached.filename());
        for (const char* ext : {".png", ".mtl", ".obj"}) {
          const std::filesystem::path name = std::filesystem::path(cached).replace_extension(ext).filename();
          if (std::filesystem::exists(staging / name, ec)) std::filesystem::rename(staging / name, cached.parent_path() / name, ec);
        }
      } catch (const std::exception&) {
        // Left uncached.
      }
      std::filesystem::remove_all(staging, ec);
      mesh = build.mesh;
    } catch (const Error& e) {
      spec.at("build").fail(e.what());
    }
  }
  if (spec.boolean_or("centre", false)) {
    const Vec3 centre = mesh.bounds().center();
    for (Vec3& p : mesh.positions) p -= centre;
  }
  return mesh;
}

void register_scene_mesh_builder() { set_volume_mesh_builder(&build_scene_mesh); }

}  // namespace trocar
