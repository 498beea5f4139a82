#pragma once
// A straight vessel for the bleeding tests and benches: a tube along x, a ring every millimetre,
// its ends held, soft tissue under gravity −z solved by XPBD, bleeding as `vessel` when opened.
#include <cmath>
#include <string>
#include <vector>

#include "trocar/mesh/inguinal_anatomy.h"
#include "trocar/sim/world.h"

namespace trocar::test {

/// Adds a vessel from centre − (half_length, 0, 0) to centre + (half_length, 0, 0) (m), a tube of
/// `radius` with `segments` around it, every vertex farther than `held_beyond` from its middle
/// along x fixed.
inline TissueBody& add_held_vessel(World& world, const std::string& name, const Vec3& centre, Real half_length,
                                   Real radius, std::size_t segments, Real held_beyond, const VesselSpec& vessel) {
  std::vector<Vec3> axis;
  const int rings = static_cast<int>(std::lround(2 * half_length / 0.001));
  for (int k = 0; k <= rings; ++k) axis.emplace_back(centre.x() + (-half_length + 0.001 * k), centre.y(), centre.z());
  const TriMesh tube = make_tube(axis, radius, segments);
  FixedSelection fixed;
  for (std::uint32_t v = 0; v < tube.positions.size(); ++v)
    if (std::abs(tube.positions[v].x() - centre.x()) > held_beyond) fixed.indices.push_back(v);
  TissueBody& t = world.add_tissue(name, tube, material_preset("soft"), fixed, Vec3(0, 0, -9.81), IntegratorKind::kXpbd);
  t.bleeds = vessel;
  return t;
}

}  // namespace trocar::test
