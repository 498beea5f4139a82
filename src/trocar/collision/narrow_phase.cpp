#include "trocar/collision/narrow_phase.h"

#include <algorithm>
#include <limits>

#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace {

// Cheap, conservative rejection before the exact test: all of p0..p2 strictly on one side of
// the plane of q0q1q2, by more than 1e-9 of the pair's size L (intersect_triangles counts
// only distances ≤ 1e-12·L as touching, so nothing it accepts is rejected here). Works with the
// unnormalised normal n (no square root): d_i = n·(p_i − q0) and the threshold 1e-9·L·|n| are
// compared squared. Skipped (returns false) for slivers, whose plane is ill-conditioned.
bool separated_by_plane(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& q0, const Vec3& q1,
                        const Vec3& q2, Real size) {
  const Vec3 e1 = q1 - q0;
  const Vec3 e2 = q2 - q0;
  const Vec3 n = e1.cross(e2);
  const Real n2 = n.squaredNorm();
  const Real longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (q2 - q1).squaredNorm()});
  if (!(n2 > 1e-6 * longest2 * longest2)) return false;
  const Real d0 = n.dot(p0 - q0);
  const Real d1 = n.dot(p1 - q0);
  const Real d2 = n.dot(p2 - q0);
  const Real threshold2 = 1e-18 * size * size * n2;
  const bool all_above = d0 > 0 && d1 > 0 && d2 > 0;
  const bool all_below = d0 < 0 && d1 < 0 && d2 < 0;
  if (!all_above && !all_below) return false;
  return d0 * d0 > threshold2 && d1 * d1 > threshold2 && d2 * d2 > threshold2;
}

Real pair_size(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1, const Vec3& b2) {
  const Vec3 lo = a0.cwiseMin(a1).cwiseMin(a2).cwiseMin(b0).cwiseMin(b1).cwiseMin(b2);
  const Vec3 hi = a0.cwiseMax(a1).cwiseMax(a2).cwiseMax(b0).cwiseMax(b1).cwiseMax(b2);
  return (hi - lo).maxCoeff();
}

}  // namespace

void narrow_phase(std::span<const CollisionObject> objects, std::span<const CandidatePair> pairs,
                  std::vector<Contact>& out) {
  out.clear();
  for (const CandidatePair& pair : pairs) {
    const CollisionObject& oa = objects[pair.object_a];
    const CollisionObject& ob = objects[pair.object_b];
    const Triangle& ta = oa.triangles[pair.triangle_a];
    const Triangle& tb = ob.triangles[pair.triangle_b];
    const Vec3& a0 = oa.positions[ta[0]];
    const Vec3& a1 = oa.positions[ta[1]];
    const Vec3& a2 = oa.positions[ta[2]];
    const Vec3& b0 = ob.positions[tb[0]];
    const Vec3& b1 = ob.positions[tb[1]];
    const Vec3& b2 = ob.positions[tb[2]];
    const Real size = pair_size(a0, a1, a2, b0, b1, b2);
    if (!(size < std::numeric_limits<Real>::infinity())) continue;  // NaN or infinite input
    if (separated_by_plane(a0, a1, a2, b0, b1, b2, size) || separated_by_plane(b0, b1, b2, a0, a1, a2, size)) continue;
    const TriTriResult r = intersect_triangles(a0, a1, a2, b0, b1, b2);
    if (!r.intersects) continue;
    Contact c;
    c.object_a = pair.object_a;
    c.object_b = pair.object_b;
    c.triangle_a = pair.triangle_a;
    c.triangle_b = pair.triangle_b;
    c.kind = contact_kind(oa.role, ob.role);
    c.coplanar = r.coplanar;
    c.segment_p = r.p;
    c.segment_q = r.q;
    out.push_back(c);
  }
  // std::sort does not allocate (introsort in place).
  std::sort(out.begin(), out.end(), contact_less);
}

}  // namespace trocar
