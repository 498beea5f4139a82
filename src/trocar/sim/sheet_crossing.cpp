// The tunneling metric on an open tissue (a sheet), DESIGN.md §6: an instrument vertex that
// crosses the surface within one step without a contact being reported for it. A sheet has no
// inside, so a vertex's state is its side: the sign of its signed distance (the pseudonormal of
// its closest feature). The side is unknown while that feature is on the sheet's border (the
// vertex can go around the edge) or the vertex is away from the sheet. No penetration depth is
// measured on sheets (docs/scene.md).
#include <cmath>
#include <limits>

#include "trocar/sim/simulation.h"

namespace trocar {

Real Simulation::sheet_side(const InstrumentBody& body, std::size_t i, std::size_t t, std::uint32_t v,
                            const SignedDistanceResult& r) {
  constexpr Real kUnknownSide = std::numeric_limits<Real>::quiet_NaN();
  const std::size_t nt = world_.tissues.size();
  const SheetBoundary& border = sheets_[t];
  const std::span<const Triangle> triangles = world_.tissues[t]->settings.triangles;
  if (r.triangle >= triangles.size() || r.distance == 0 ||
      border.on_boundary(r.triangle, triangles[r.triangle], r.feature, r.feature_index))
    return kUnknownSide;
  const Real before = previous_distance_[i * nt + t][v];
  const bool side = r.distance > 0;
  // A side change with the side known on both steps, and no contact on the vertex this step.
  if (std::isnan(before) || (before > 0) == side || touched_[i][v] != 0) return r.distance;
  // Did the vertex cross the surface the detection saw (the tissue's positions before this
  // step's deformation), or did the sheet move over a vertex after the response (answered by
  // the next detection, as for closed tissues)?
  const Vec3& p = body.instrument.world_positions()[v];
  const SignedDistanceResult at_start = start_surface(t).signed_distance(p, r.triangle);
  const bool start_border = at_start.triangle >= triangles.size() ||
                            border.on_boundary(at_start.triangle, triangles[at_start.triangle], at_start.feature,
                                               at_start.feature_index);
  if (!start_border && at_start.distance != 0 && (at_start.distance > 0) == side) ++metrics_.tunneling_events;
  return r.distance;
}

}  // namespace trocar
