#include "trocar/mesh/sheet_boundary.h"

#include "trocar/mesh/topology.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

SheetBoundary::SheetBoundary(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  TriMesh mesh;
  mesh.positions.assign(positions.begin(), positions.end());
  mesh.triangles.assign(triangles.begin(), triangles.end());
  *this = SheetBoundary(MeshTopology(mesh));
}

SheetBoundary::SheetBoundary(const MeshTopology& topology) {
  edge_bits_.assign(topology.triangle_count(), 0);
  vertex_.assign(topology.vertex_count(), 0);
  for (const std::uint32_t e : topology.boundary_edges()) {
    vertex_[topology.edge(e).v0] = 1;
    vertex_[topology.edge(e).v1] = 1;
    ++boundary_edges_;
  }
  for (std::size_t t = 0; t < topology.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = topology.triangle_edges(t)[static_cast<std::size_t>(k)];
      if (e != MeshTopology::kNone && topology.edge_valence(e) == 1)
        edge_bits_[t] = static_cast<std::uint8_t>(edge_bits_[t] | (1u << k));
    }
}

}  // namespace trocar
