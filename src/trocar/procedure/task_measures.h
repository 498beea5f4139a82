#pragma once
/// The completion tests' measures (docs/procedure.md): the share of a surface beyond a plane, the
/// share of a required region of the wall a sheet covers, and the area of a sheet folded over.
/// Each is a scan over the tissue's triangles with no allocation after construction.
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// A plane through `point` with unit `normal` (the side it points to is "beyond").
struct WallPlane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3(0, 0, 1);
};

/// Area of the surface (m²) and the part of it beyond the plane (each triangle clipped exactly).
struct AreaSplit {
  Real total = 0;
  Real beyond = 0;
  Real fraction() const { return total > 0 ? beyond / total : 0; }
};
AreaSplit area_beyond_plane(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                            const WallPlane& plane);

/// Area (m²) of the triangles whose normal opposes the sheet's prevailing side of `normal` (the
/// sign of the area-weighted Σ nₜ·normal): the part of a sheet folded back over itself.
Real flipped_area(std::span<const Vec3> positions, std::span<const Triangle> triangles, const Vec3& normal);

/// The region of the wall a mesh must cover: the MPO polygon and a disc about the defect,
/// sampled on a square grid in the wall plane. covered_fraction() marks the samples under the
/// sheet's triangles projected onto the plane.
class CoverageRegion {
 public:
  CoverageRegion() = default;
  /// `polygon`: the MPO's corners (any count; < 3 adds nothing), projected onto the plane.
  /// `centre`, `radius`: the disc (radius ≤ 0 adds nothing). `spacing` > 0: the grid's step (m).
  CoverageRegion(const WallPlane& plane, std::span<const Vec3> polygon, const Vec3& centre, Real radius,
                 Real spacing);

  /// Number of required samples.
  std::size_t samples() const { return required_count_; }
  /// Share of the required samples under the sheet (1 when there are none).
  Real covered_fraction(std::span<const Vec3> positions, std::span<const Triangle> triangles);

  /// World point → plane coordinates (m).
  Vec2 to_plane(const Vec3& p) const;

 private:
  WallPlane plane_;
  Vec3 u_ = Vec3::UnitX(), v_ = Vec3::UnitY();
  Vec2 origin_ = Vec2::Zero();  ///< the grid's lower corner (plane coordinates)
  Real spacing_ = 1;
  std::size_t nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> required_;  ///< per grid node
  std::vector<std::uint8_t> covered_;   ///< per grid node, this evaluation
  std::size_t required_count_ = 0;
};

}  // namespace trocar
