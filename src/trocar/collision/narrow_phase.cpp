#include "trocar/collision/narrow_phase.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace {

// Cheap, conservative rejections before the exact test (intersect_triangles). Each may only
// reject pairs that intersect_triangles rejects too, so they change nothing but the time; the
// margins below are orders of magnitude wider than the test's tolerance (kTriTriTolerance = 1e-12
// of the pair's size L) and than its rounding errors.

// A triangle's plane: the unnormalised normal n = (q1 − q0) × (q2 − q0) (no square root), |n|²,
// and whether the triangle is well shaped (not a sliver: |n|² > 1e-6·(longest edge)⁴). Computed
// once per run of candidates that share the triangle (the broad phases emit a triangle's
// partners one after another), from differences of the triangle's own corners, so its rounding
// follows the triangle's size, not its distance from the origin.
struct TrianglePlane {
  std::uint64_t key = ~std::uint64_t{0};  // (object << 32) | triangle; none yet
  Vec3 q0;
  Vec3 n;
  Real n2 = 0;
  bool well_shaped = false;
};

const TrianglePlane& plane_of(TrianglePlane& cache, std::uint32_t object, std::uint32_t triangle, const Vec3& q0,
                              const Vec3& q1, const Vec3& q2) {
  const std::uint64_t key = (std::uint64_t{object} << 32) | triangle;
  if (cache.key == key) return cache;
  cache.key = key;
  const Vec3 e1 = q1 - q0;
  const Vec3 e2 = q2 - q0;
  cache.q0 = q0;
  cache.n = e1.cross(e2);
  cache.n2 = cache.n.squaredNorm();
  const Real longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (q2 - q1).squaredNorm()});
  cache.well_shaped = cache.n2 > 1e-6 * longest2 * longest2;
  return cache;
}

// Signed distances (× |n|) of p0..p2 to a triangle's plane. Each p − q0 is a difference of two
// nearby points, as accurate as the pair's own coordinates allow.
void plane_distances(const TrianglePlane& plane, const Vec3& p0, const Vec3& p1, const Vec3& p2, Real (&d)[3]) {
  d[0] = plane.n.dot(p0 - plane.q0);
  d[1] = plane.n.dot(p1 - plane.q0);
  d[2] = plane.n.dot(p2 - plane.q0);
}

// Plane rejection: all of p0..p2 strictly on one side of the plane, by more than 1e-9·L
// (compared squared, d_i² > (1e-9·L)²·|n|²). Skipped (false) for slivers, whose plane is
// ill-conditioned.
bool separated_by_plane(const TrianglePlane& plane, const Real (&d)[3], Real size) {
  if (!plane.well_shaped) return false;
  const bool all_above = d[0] > 0 && d[1] > 0 && d[2] > 0;
  const bool all_below = d[0] < 0 && d[1] < 0 && d[2] < 0;
  if (!all_above && !all_below) return false;
  const Real threshold2 = 1e-18 * size * size * plane.n2;
  return d[0] * d[0] > threshold2 && d[1] * d[1] > threshold2 && d[2] * d[2] > threshold2;
}

// Extends [lo, hi] by the projections on `dir` of the part of triangle p0p1p2 (corners relative
// to a common origin) that lies within the slab |d| ≤ tau of the other plane, d being the
// corners' signed distances (× |n|): per edge, the sub-segment inside the slab.
void slab_interval(const Vec3 (&p)[3], const Real (&d)[3], Real tau, const Vec3& dir, Real& lo, Real& hi) {
  Real proj[3];
  for (int i = 0; i < 3; ++i) proj[i] = dir.dot(p[i]);
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    const Real di = d[i];
    const Real dj = d[j];
    if ((di > tau && dj > tau) || (di < -tau && dj < -tau)) continue;  // edge outside the slab
    Real l0 = 0;
    Real l1 = 1;
    const Real dd = dj - di;
    if (std::abs(dd) > tau) {
      // d(λ) = di + λ·dd ∈ [−tau, tau] for λ between these two values.
      const Real a = (-tau - di) / dd;
      const Real b = (tau - di) / dd;
      l0 = std::max(l0, std::min(a, b));
      l1 = std::min(l1, std::max(a, b));
      if (l0 > l1) {  // only by rounding (the edge reaches the slab): keep the nearer end
        l0 = l1 = std::clamp(0.5 * (l0 + l1), Real{0}, Real{1});
      }
    }
    // Nearly parallel to the plane (|dd| ≤ tau): the whole edge is within 2·tau, keep it all.
    const Real x0 = proj[i] + l0 * (proj[j] - proj[i]);
    const Real x1 = proj[i] + l1 * (proj[j] - proj[i]);
    lo = std::min({lo, x0, x1});
    hi = std::max({hi, x0, x1});
  }
}

// Interval rejection (Möller's test, made conservative): when the planes cross at a clear angle
// (sin θ ≥ 0.01) and neither triangle is a sliver, the parts of A and B near the other's plane
// (within 1e-9·L, far more than the exact test's snapping and rounding) project on the
// intersection line direction nA × nB to two intervals; the pair is rejected when they are apart
// by more than 1e-7·L. Every point the exact test puts on a trace lies in those parts, and its
// ordering direction differs from the line by far less than that margin allows.
bool separated_on_line(const Vec3 (&a)[3], const Vec3 (&b)[3], const TrianglePlane& plane_a, const Real (&d_a)[3],
                       const TrianglePlane& plane_b, const Real (&d_b)[3], Real size) {
  // d_a: A's corners to B's plane (× |nB|); d_b: B's corners to A's plane (× |nA|).
  if (!plane_a.well_shaped || !plane_b.well_shaped) return false;
  const Vec3 dir = plane_a.n.cross(plane_b.n);  // nA × nB
  const Real dir2 = dir.squaredNorm();
  if (!(dir2 >= 1e-4 * plane_a.n2 * plane_b.n2)) return false;  // sin²θ < 1e-4
  constexpr Real kInf = std::numeric_limits<Real>::infinity();
  Real a_lo = kInf, a_hi = -kInf, b_lo = kInf, b_hi = -kInf;
  slab_interval(a, d_a, 1e-9 * size * std::sqrt(plane_b.n2), dir, a_lo, a_hi);
  slab_interval(b, d_b, 1e-9 * size * std::sqrt(plane_a.n2), dir, b_lo, b_hi);
  if (!(a_lo <= a_hi) || !(b_lo <= b_hi)) return false;  // (not expected: both straddle)
  const Real gap = std::max(a_lo, b_lo) - std::min(a_hi, b_hi);  // in units of |dir|
  return gap > 0 && gap * gap > 1e-14 * size * size * dir2;
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
  TrianglePlane cache_a;
  TrianglePlane cache_b;
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
    const TrianglePlane& plane_b = plane_of(cache_b, pair.object_b, pair.triangle_b, b0, b1, b2);
    Real d_a[3];  // A's corners to B's plane
    plane_distances(plane_b, a0, a1, a2, d_a);
    if (separated_by_plane(plane_b, d_a, size)) continue;
    const TrianglePlane& plane_a = plane_of(cache_a, pair.object_a, pair.triangle_a, a0, a1, a2);
    Real d_b[3];  // B's corners to A's plane
    plane_distances(plane_a, b0, b1, b2, d_b);
    if (separated_by_plane(plane_a, d_b, size)) continue;
    // Relative to a0, so that the projections' rounding follows the pair's size, not its
    // position.
    const Vec3 ra[3] = {Vec3::Zero(), a1 - a0, a2 - a0};
    const Vec3 rb[3] = {b0 - a0, b1 - a0, b2 - a0};
    if (separated_on_line(ra, rb, plane_a, d_a, plane_b, d_b, size)) continue;
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
