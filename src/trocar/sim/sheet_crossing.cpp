// The penetration and tunneling metrics on an open tissue (a sheet), docs/scene.md. A sheet has
// no inside, so a vertex's state is its side: the sign of its signed distance (the pseudonormal
// of its closest feature). The side is unknown while that feature is on the sheet's border (the
// vertex can go around the edge) or the vertex is away from the sheet. A vertex whose known side
// changes has crossed the sheet's interior: from then until it crosses back (or its side is
// lost) it is "through", and its distance to the sheet is its penetration depth. Tunneling:
// (a) a crossing with no contact on the vertex that the detection's surface confirms, (b) a
// through vertex's depth first exceeding the instrument's thickness.
#include <algorithm>
#include <cmath>
#include <limits>

#include "trocar/sim/penetration_meter.h"

namespace trocar {

Real PenetrationMeter::sheet_side(const InstrumentBody& body, std::size_t i, std::size_t t, std::uint32_t v,
                            const SignedDistanceResult& r) {
  constexpr Real kUnknownSide = std::numeric_limits<Real>::quiet_NaN();
  const SheetBoundary& border = sheets_[t];
  const std::span<const Triangle> triangles = world_.tissues[t]->settings.triangles;
  std::uint8_t& through = through_[pair(i, t)][v];
  if (r.triangle >= triangles.size() || r.distance == 0 ||
      border.on_boundary(r.triangle, triangles[r.triangle], r.feature, r.feature_index)) {
    through = 0;
    return kUnknownSide;
  }
  const Real before = previous_distance_[pair(i, t)][v];
  const bool side = r.distance > 0;
  const bool crossed = !std::isnan(before) && (before > 0) != side;  // side known on both steps
  // Depth before this step on the same side (0 if the vertex just arrived on it).
  const Real depth_before = through != 0 && !crossed ? std::abs(before) : 0.0;
  if (crossed) through ^= 1;
  if (crossed && touched_[i][v] == 0) {
    // Did the vertex cross the surface the detection saw (the tissue's positions before this
    // step's deformation), or did the sheet move over a vertex after the response (answered by
    // the next detection, as for closed tissues)?
    const Vec3& p = body.instrument.world_positions()[v];
    const SignedDistanceResult at_start = start_surface(t).signed_distance(p, r.triangle);
    const bool start_border = at_start.triangle >= triangles.size() ||
                              border.on_boundary(at_start.triangle, triangles[at_start.triangle], at_start.feature,
                                                 at_start.feature_index);
    if (!start_border && at_start.distance != 0 && (at_start.distance > 0) == side)
      ++reading_.tunneling_events;  // (a)
  }
  if (through != 0) {
    const Real depth = std::abs(r.distance);
    ++reading_.vertices_inside;
    reading_.penetration_max = std::max(reading_.penetration_max, depth);
    if (depth > body.thickness && !(depth_before > body.thickness)) ++reading_.tunneling_events;  // (b)
  }
  return r.distance;
}

}  // namespace trocar
