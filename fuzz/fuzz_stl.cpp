// libFuzzer harness for read_stl: any exception other than trocar::FileError, any crash, hang
// or sanitizer report is a finding; a mesh that loads must satisfy the TriMesh invariants, and
// welding must leave no two vertices at the same position.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "trocar/mesh/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const trocar::TriMesh mesh = trocar::read_stl(bytes, "fuzz.stl");
    if (!mesh.indices_valid() || mesh.triangles.empty()) __builtin_trap();
    if (!mesh.normals.empty() || !mesh.texcoords.empty()) __builtin_trap();
    // Every vertex is used (STL has no unused vertices) and positions are finite.
    if (mesh.positions.size() > 3 * mesh.triangles.size()) __builtin_trap();
    for (const trocar::Vec3& p : mesh.positions)
      if (!p.allFinite()) __builtin_trap();
    // Small meshes: check welding pairwise (bounded cost).
    if (mesh.positions.size() <= 64)
      for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        for (std::size_t j = i + 1; j < mesh.positions.size(); ++j)
          if (mesh.positions[i] == mesh.positions[j]) __builtin_trap();
  } catch (const trocar::FileError&) {
    // malformed input, reported properly
  }
  return 0;
}
