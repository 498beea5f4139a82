#pragma once
// Shared body of the reader fuzz targets: a reader must either return a valid mesh or throw
// trocar::FileError. Any other exception escapes (a finding); a broken invariant traps.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "trocar/mesh/io/mesh_io.h"

namespace trocar::fuzz {

/// Traps unless the mesh satisfies what every reader promises: at least one triangle, indices in
/// range, attribute arrays of valid sizes, every position, normal and texcoord finite.
inline void check_mesh(const TriMesh& mesh) {
  if (!mesh.indices_valid() || mesh.triangles.empty()) __builtin_trap();
  for (const Vec3& p : mesh.positions)
    if (!p.allFinite()) __builtin_trap();
  for (const Vec3& n : mesh.normals)
    if (!n.allFinite()) __builtin_trap();
  for (const Vec2& t : mesh.texcoords)
    if (!t.allFinite()) __builtin_trap();
}

/// Runs `read(bytes, name)` on the fuzz input, checks the mesh, then calls `extra(mesh)` for
/// format-specific invariants. Malformed input reported as FileError is fine.
template <typename Read, typename Extra>
int run_reader(const std::uint8_t* data, std::size_t size, Read read, const char* name, Extra extra) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const TriMesh mesh = read(bytes, name);
    check_mesh(mesh);
    extra(mesh);
  } catch (const FileError&) {
    // malformed input, reported properly
  }
  return 0;
}

/// As above with no format-specific check.
template <typename Read>
int run_reader(const std::uint8_t* data, std::size_t size, Read read, const char* name) {
  return run_reader(data, size, read, name, [](const TriMesh&) {});
}

}  // namespace trocar::fuzz
