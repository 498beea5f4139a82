// libFuzzer harness for read_obj: any exception other than trocar::FileError, any crash, hang
// or sanitizer report is a finding; a mesh that loads must satisfy the TriMesh invariants.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "trocar/mesh/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const trocar::TriMesh mesh = trocar::read_obj(bytes, "fuzz.obj");
    if (!mesh.indices_valid() || mesh.triangles.empty()) __builtin_trap();
    for (const trocar::Vec3& p : mesh.positions)
      if (!p.allFinite()) __builtin_trap();
    for (const trocar::Vec3& n : mesh.normals)
      if (!n.allFinite()) __builtin_trap();
    for (const trocar::Vec2& t : mesh.texcoords)
      if (!t.allFinite()) __builtin_trap();
  } catch (const trocar::FileError&) {
    // malformed input, reported properly
  }
  return 0;
}
