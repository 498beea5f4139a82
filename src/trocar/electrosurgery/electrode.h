#pragma once
/// An electrode (the hook) and where its power goes (docs/electrosurgery.md, "Energy").
///
/// The instrument's uninsulated end, its vertices within `active_length` of the tip along the
/// shaft, is the electrode. With the pedal down, a tissue triangle within `reach` of one of those
/// vertices (touching, or across the gap a cutting arc jumps) takes a share of the power in
/// proportion to its rest area: the heated tissue is the touched surface, so the burn's
/// resolution is the mesh's (a triangle heats as one).
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// An instrument's electrode (scene key "electrode"; power 0: not an electrode).
struct ElectrodeSpec {
  /// W: the generator's setting (cut and coagulation are typically 30–50 W for a monopolar hook:
  /// Massarweh et al., J Am Coll Surg 202:520, 2006). 0: the instrument is not an electrode.
  Real power = 0;
  Real active_length = 0.006;  ///< m of the tip left uninsulated (a hook's foot and elbow)
  Real reach = 0.0005;         ///< m: how far from the metal the tissue still takes energy (arc gap)
};

/// The electrode's surface as points in the instrument's local frame: its vertices within
/// `active_length` of the tip end along `shaft` (unit, tip → handle), and points every `spacing`
/// (at most) along the edges between two of them, so that a long thin part (the hook's 5 mm foot
/// is one ring of vertices at each end) touches what lies under its middle. Empty when the mesh is.
std::vector<Vec3> electrode_points(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                                   const Vec3& shaft, Real active_length, Real spacing);

/// Marks in `touched` (one per triangle) the triangles within `reach` of any of `points` (the
/// electrode's vertices in the world) and returns their total rest area (m², 0: none). A box test
/// rejects far triangles before the exact distance; no allocation.
Real touch_triangles(std::span<const Vec3> points, std::span<const Vec3> positions, std::span<const Triangle> triangles,
                     std::span<const Real> rest_areas, Real reach, std::span<std::uint8_t> touched);

/// Adds to `out` the touched triangles' shares of `power` (W): P A_k / `total_area`, where the
/// total is over every tissue the electrode touches. No allocation.
void share_power(Real power, Real total_area, std::span<const std::uint8_t> touched, std::span<const Real> rest_areas,
                 std::span<Real> out);

}  // namespace trocar
