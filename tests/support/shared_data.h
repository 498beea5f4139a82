#pragma once
/// Where the tests find the third-party meshes of ../shared/data/meshes (SOURCES.md there), and
/// whether they are there at all: a user's clone has no ../shared, so every test that reads them
/// asks here and skips when they are absent. TROCAR_HIDE_SHARED=1 in the environment hides them
/// even when present (.ci/run runs those tests once that way: the fresh-clone check).
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace trocar::test {

/// True when TROCAR_HIDE_SHARED is set to something other than "" or "0".
inline bool shared_data_hidden() {
  const char* hide = std::getenv("TROCAR_HIDE_SHARED");
  return hide != nullptr && *hide != 0 && std::string_view(hide) != "0";
}

/// The shared meshes folder (TROCAR_SHARED_MESHES_DEFAULT, set by CMake to ../shared/data/meshes
/// beside the source tree), or nothing when it is absent or hidden.
inline std::optional<std::filesystem::path> shared_meshes_dir() {
  if (shared_data_hidden()) return std::nullopt;
  const std::filesystem::path dir(TROCAR_SHARED_MESHES_DEFAULT);
  if (!std::filesystem::is_directory(dir)) return std::nullopt;
  return dir;
}

/// The path of one shared mesh, or nothing when the folder or the file is absent (or hidden).
inline std::optional<std::filesystem::path> shared_mesh_path(std::string_view file) {
  const std::optional<std::filesystem::path> dir = shared_meshes_dir();
  if (!dir) return std::nullopt;
  std::filesystem::path path = *dir / file;
  if (!std::filesystem::exists(path)) return std::nullopt;
  return path;
}

/// The reason a test skips for want of `file`.
inline std::string shared_absent(std::string_view file) {
  return std::string("shared mesh ") + std::string(file) +
         (shared_data_hidden() ? " hidden (TROCAR_HIDE_SHARED)" : " absent (no ../shared/data/meshes)");
}

/// The path of one shared image volume (../shared/data/volumes, beside the meshes folder), or
/// nothing when it is absent or hidden.
inline std::optional<std::filesystem::path> shared_volume_path(std::string_view file) {
  if (shared_data_hidden()) return std::nullopt;
  std::filesystem::path path = std::filesystem::path(TROCAR_SHARED_MESHES_DEFAULT).parent_path() / "volumes" / file;
  if (!std::filesystem::exists(path)) return std::nullopt;
  return path;
}

}  // namespace trocar::test

/// Declares `const std::filesystem::path var` for the shared mesh `file`, or skips the test.
#define TROCAR_SHARED_MESH_OR_SKIP(var, file)                                        \
  const std::optional<std::filesystem::path> var##_found = ::trocar::test::shared_mesh_path(file); \
  if (!var##_found) GTEST_SKIP() << ::trocar::test::shared_absent(file);             \
  const std::filesystem::path& var = *var##_found

/// Declares `const std::filesystem::path var` for the shared volume `file`, or skips the test.
#define TROCAR_SHARED_VOLUME_OR_SKIP(var, file)                                        \
  const std::optional<std::filesystem::path> var##_found = ::trocar::test::shared_volume_path(file); \
  if (!var##_found) GTEST_SKIP() << "shared volume " << (file) << " absent or hidden";  \
  const std::filesystem::path& var = *var##_found
