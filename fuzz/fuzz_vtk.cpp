// libFuzzer target for read_vtk: any input must either give a valid mesh or throw FileError.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "trocar/mesh/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const trocar::TriMesh mesh = trocar::read_vtk(bytes, "fuzz.vtk");
    if (!mesh.indices_valid()) __builtin_trap();
    for (const trocar::Vec3& p : mesh.positions)
      if (!p.allFinite()) __builtin_trap();
    for (const trocar::Vec3& n : mesh.normals)
      if (!n.allFinite()) __builtin_trap();
  } catch (const trocar::FileError&) {
    // Malformed input, reported properly.
  }
  return 0;  // any other exception escapes and is a finding
}
