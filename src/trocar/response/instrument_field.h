#pragma once
/// The signed distance to a rigid instrument, in the instrument's own frame, for the `sdf`
/// response (docs/response.md "Contact as a constraint"). Built once when the instrument is
/// loaded: the instrument never deforms, so its distance needs no refit, only the pose's inverse.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "trocar/core/aabb.h"
#include "trocar/core/types.h"
#include "trocar/geometry/signed_distance.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Exact signed distance to a closed instrument mesh (MeshDistance over its local vertices) and a
/// coarse grid of the same distance at cell centres, which rules most query points out with one
/// lookup: the distance is 1-Lipschitz, so for p in the cell of centre c,
/// d(p) ≥ d(c) − |p − c| ≥ d(c) − h√3/2 (h the cell edge). Outside the grid's box (the mesh's box
/// grown by `pad`), the distance to the box bounds it from below. This is SOFA's distance-grid
/// idea used as a cull in front of the exact query, not as the answer: the exact query keeps thin
/// features (a 1 mm hook) right at any grid size.
class InstrumentField {
 public:
  /// An empty field: every lower bound +inf, every query +inf.
  InstrumentField() = default;
  /// Builds the field of `local_mesh` (metres, the instrument's local frame; closed and outward
  /// for the sign to mean inside). `pad` (m) grows the grid's box; the grid has at most
  /// `max_cells` cells (cubic cells, edge chosen to fit). Allocates; O(max_cells) exact queries.
  /// `sample_spacing` (m) sets samples().
  explicit InstrumentField(const TriMesh& local_mesh, Real pad = 0.004, std::size_t max_cells = 1u << 16,
                           Real sample_spacing = 0.001);

  /// A value ≤ the signed distance of local point p (m); +inf for an empty mesh. No allocation.
  Real lower_bound(const Vec3& p) const;
  /// The exact signed distance of local point p (negative inside); `hint` as MeshDistance.
  SignedDistanceResult query(const Vec3& p, std::uint32_t hint = MeshDistance::kNoTriangle) const {
    return exact_ ? exact_->signed_distance(p, hint) : SignedDistanceResult{};
  }
  /// Cell edge of the grid (m); 0 for an empty field.
  Real cell_size() const { return cell_; }
  /// The grid's box in the local frame (the mesh's box grown by pad).
  const Aabb& box() const { return box_; }
  /// True when built from a mesh with triangles.
  bool empty() const { return values_.empty(); }

  /// Points on the instrument's surface for the face pushes of the sdf response (local frame):
  /// every vertex, then points every `sample_spacing` along each edge longer than it (a tissue
  /// face can close over the middle of a 5 mm wire segment that has vertices only at its ends).
  std::span<const Vec3> samples() const { return samples_; }
  /// For each sample, the instrument vertices it stands for: a vertex twice, an edge point its
  /// edge's two ends.
  std::span<const std::array<std::uint32_t, 2>> sample_vertices() const { return sample_vertices_; }

 private:
  std::optional<MeshDistance> exact_;
  Aabb box_;
  Real cell_ = 0;
  Real slack_ = 0;  ///< h√3/2
  std::size_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<float> values_;  ///< d(c) − slack at each cell centre, rounded down to float
  std::vector<Vec3> samples_;
  std::vector<std::array<std::uint32_t, 2>> sample_vertices_;
};

}  // namespace trocar
