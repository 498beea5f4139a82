#pragma once
/// The boundary of an open tissue surface (a sheet such as the peritoneum or the prosthetic mesh):
/// a point whose closest feature lies on the sheet's border can pass around that edge without
/// crossing the sheet, so its side there is unknown. The tunneling metric treats it so
/// (docs/scene.md, "tunneling"), and the tissue contact keeps no side there (docs/response.md,
/// "Tissue against tissue").
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/geometry/closest_point.h"
#include "trocar/mesh/topology.h"

namespace trocar {

class SheetBoundary {
 public:
  SheetBoundary() = default;
  /// Marks the boundary edges (one triangle) and their vertices of the triangles (indices into
  /// positions; throws trocar::Error for an index out of range).
  SheetBoundary(std::span<const Vec3> positions, std::span<const Triangle> triangles);
  /// The same from a surface's topology already built.
  explicit SheetBoundary(const MeshTopology& topology);

  /// True when feature `feature` (index k) of triangle t, whose vertices are `tri`, lies on the
  /// boundary: a boundary edge, or a vertex of one. A face never does.
  bool on_boundary(std::uint32_t t, const Triangle& tri, TriangleFeature feature, int k) const {
    switch (feature) {
      case TriangleFeature::kFace: return false;
      case TriangleFeature::kEdge: return (edge_bits_[t] >> k & 1u) != 0;
      case TriangleFeature::kVertex: return vertex_[tri[static_cast<std::size_t>(k)]] != 0;
    }
    return true;
  }
  /// Number of boundary edges (0 for a closed surface).
  std::size_t boundary_edge_count() const { return boundary_edges_; }

 private:
  std::vector<std::uint8_t> edge_bits_;  ///< per triangle: bit k set when local edge k is a boundary edge
  std::vector<std::uint8_t> vertex_;     ///< per vertex: 1 on the boundary
  std::size_t boundary_edges_ = 0;
};

}  // namespace trocar
