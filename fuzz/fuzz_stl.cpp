// libFuzzer target for read_stl: any input must either give a valid mesh or throw FileError
// (fuzz_common.h); also checks STL's own promises: no attributes, every vertex used, welded.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return trocar::fuzz::run_reader(data, size, trocar::read_stl, "fuzz.stl", [](const trocar::TriMesh& mesh) {
    if (!mesh.normals.empty() || !mesh.texcoords.empty()) __builtin_trap();
    // A soup welded in order of appearance uses every vertex, so there are at most 3 per triangle.
    if (mesh.positions.size() > 3 * mesh.triangles.size()) __builtin_trap();
    // Small meshes: check the welding pairwise (bounded cost).
    if (mesh.positions.size() <= 64)
      for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        for (std::size_t j = i + 1; j < mesh.positions.size(); ++j)
          if (mesh.positions[i] == mesh.positions[j]) __builtin_trap();
  });
}
