// intersect_triangles against an independent brute-force reference on random pairs.
//
// Reference: two closed triangles in general position intersect iff an edge of one pierces the
// other, and the ends of their intersection segment are exactly those piercing points. Each
// edge–triangle test uses only signs of tetrahedron volumes (orient3d): segment pq crosses the
// plane of abc iff orient(a,b,c,p) and orient(a,b,c,q) differ in sign, and the line pq passes
// inside abc iff orient(p,q,a,b), orient(p,q,b,c), orient(p,q,c,a) share a sign. The smallest of
// these volumes (relative to L³) measures how well-conditioned the reference answer is.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "trocar/geometry/closest_point.h"
#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace {

using Tri = std::array<Vec3, 3>;

Real orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

struct RefHit {
  bool hit = false;
  Vec3 point = Vec3::Zero();
  Real margin = 0;  // smallest |volume| / L³ that decided the answer
};

RefHit ref_segment_triangle(const Vec3& p, const Vec3& q, const Tri& t, Real size3) {
  RefHit r;
  const Real op = orient(t[0], t[1], t[2], p);
  const Real oq = orient(t[0], t[1], t[2], q);
  const Real e0 = orient(p, q, t[0], t[1]);
  const Real e1 = orient(p, q, t[1], t[2]);
  const Real e2 = orient(p, q, t[2], t[0]);
  r.margin = std::min({std::abs(op), std::abs(oq), std::abs(e0), std::abs(e1), std::abs(e2)}) /
             size3;
  const bool crosses = (op > 0 && oq < 0) || (op < 0 && oq > 0);
  const bool inside = (e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0);
  r.hit = crosses && inside;
  if (r.hit) r.point = p + (op / (op - oq)) * (q - p);
  return r;
}

Real pair_size(const Tri& a, const Tri& b) {
  Real s = 0;
  for (const Tri* t : {&a, &b}) {
    for (const Vec3& v : *t) s = std::max(s, (v - a[0]).cwiseAbs().maxCoeff());
  }
  return std::max(s, Real{1e-300});
}

struct RefTriTri {
  bool intersects = false;
  int hits = 0;
  std::array<Vec3, 6> points;
  Real margin = 1e300;
};

RefTriTri ref_tri_tri(const Tri& a, const Tri& b) {
  const Real size = pair_size(a, b);
  const Real size3 = size * size * size;
  RefTriTri r;
  for (int side = 0; side < 2; ++side) {
    const Tri& s = side == 0 ? a : b;
    const Tri& t = side == 0 ? b : a;
    for (int k = 0; k < 3; ++k) {
      const RefHit h = ref_segment_triangle(s[k], s[(k + 1) % 3], t, size3);
      r.margin = std::min(r.margin, h.margin);
      if (h.hit) r.points[r.hits++] = h.point;
    }
  }
  r.intersects = r.hits > 0;
  return r;
}

TriTriResult run(const Tri& a, const Tri& b) {
  return intersect_triangles(a[0], a[1], a[2], b[0], b[1], b[2]);
}

Real distance_to(const Tri& t, const Vec3& p) {
  return (closest_point_on_triangle(p, t[0], t[1], t[2]).point - p).norm();
}

// Largest distance of P or Q from either triangle (0 when they do not intersect).
Real off_both(const TriTriResult& r, const Tri& a, const Tri& b) {
  if (!r.intersects) return 0;
  return std::max({distance_to(a, r.p), distance_to(a, r.q), distance_to(b, r.p),
                   distance_to(b, r.q)});
}

bool finite(const TriTriResult& r) { return r.p.allFinite() && r.q.allFinite(); }

class Random {
 public:
  explicit Random(std::uint64_t seed) : rng_(seed) {}
  Real uniform(Real lo = -1, Real hi = 1) { return std::uniform_real_distribution<Real>(lo, hi)(rng_); }
  Vec3 vec(Real lo = -1, Real hi = 1) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
  Vec3 unit() {
    Vec3 v;
    do v = vec(); while (v.squaredNorm() > 1 || v.squaredNorm() < 1e-6);
    return v.normalized();
  }
  Tri tri() { return {vec(), vec(), vec()}; }
  // A random point of triangle t with barycentric coordinates ≥ lo.
  Vec3 point_in(const Tri& t, Real lo = 0) {
    Real u = uniform(0, 1), v = uniform(0, 1);
    if (u + v > 1) { u = 1 - u; v = 1 - v; }
    const Real s = 1 - 3 * lo;
    return t[0] + (lo + s * u) * (t[1] - t[0]) + (lo + s * v) * (t[2] - t[0]);
  }

 private:
  std::mt19937_64 rng_;
};

Vec3 normal_of(const Tri& t) { return (t[1] - t[0]).cross(t[2] - t[0]).normalized(); }

TEST(TriTriRandom, GenericPairsAgreeWithTheEdgePiercingReference) {
  Random rnd(20240601);
  constexpr int kPairs = 100000;
  int intersecting = 0, disjoint = 0, compared_segments = 0, ill_conditioned = 0;
  int bool_mismatch = 0, asym = 0, non_finite = 0;
  Real worst_rel = 0;
  for (int i = 0; i < kPairs; ++i) {
    const Tri a = rnd.tri();
    const Vec3 shift = rnd.vec();
    const Tri b = {rnd.vec() + shift, rnd.vec() + shift, rnd.vec() + shift};
    const TriTriResult r = run(a, b);
    const RefTriTri ref = ref_tri_tri(a, b);
    if (!finite(r)) ++non_finite;
    if (r.intersects != ref.intersects) ++bool_mismatch;
    if (run(b, a).intersects != r.intersects) ++asym;
    EXPECT_FALSE(r.coplanar);
    (r.intersects ? intersecting : disjoint)++;
    if (!r.intersects || !ref.intersects) continue;
    if (ref.margin < 1e-6 || ref.hits != 2) {
      ++ill_conditioned;
      continue;
    }
    // Unordered comparison of {P, Q} with the two piercing points, relative to the pair size.
    const Real size = pair_size(a, b);
    const Real e1 = std::max((r.p - ref.points[0]).norm(), (r.q - ref.points[1]).norm());
    const Real e2 = std::max((r.p - ref.points[1]).norm(), (r.q - ref.points[0]).norm());
    worst_rel = std::max(worst_rel, std::min(e1, e2) / size);
    ++compared_segments;
  }
  EXPECT_EQ(non_finite, 0);
  EXPECT_EQ(bool_mismatch, 0);
  EXPECT_EQ(asym, 0);
  EXPECT_LT(worst_rel, 1e-9);
  // The sample must exercise both answers and nearly every intersecting pair is compared.
  EXPECT_GT(intersecting, kPairs / 20);
  EXPECT_GT(disjoint, kPairs / 20);
  EXPECT_LT(ill_conditioned, compared_segments / 100 + 1);
  std::printf("generic: %d intersecting, %d disjoint, %d segments compared (worst rel. error "
              "%.2e), %d ill-conditioned skipped\n",
              intersecting, disjoint, compared_segments, worst_rel, ill_conditioned);
}

// Checks for a near-degenerate family: never NaN; P and Q lie on both triangles within
// `on_tol`·L; where the reference is well-conditioned the boolean agrees.
struct FamilyStats {
  int pairs = 0, intersecting = 0, conditioned = 0, mismatches = 0, non_finite = 0;
  Real worst_off = 0;  // largest distance of P/Q from a triangle, relative to L
};

void check_pair(const Tri& a, const Tri& b, FamilyStats& s, bool compare_reference = true) {
  ++s.pairs;
  const TriTriResult r = run(a, b);
  if (!finite(r)) ++s.non_finite;
  if (r.intersects) ++s.intersecting;
  s.worst_off = std::max(s.worst_off, off_both(r, a, b) / pair_size(a, b));
  if (!compare_reference) return;
  const RefTriTri ref = ref_tri_tri(a, b);
  if (ref.margin > 1e-6) {
    ++s.conditioned;
    if (ref.intersects != r.intersects) ++s.mismatches;
  }
}

void report(const char* name, const FamilyStats& s) {
  std::printf("%-22s %6d pairs, %6d intersecting, %6d conditioned, worst off-triangle %.1e\n",
              name, s.pairs, s.intersecting, s.conditioned, s.worst_off);
}

TEST(TriTriRandom, NearlyCoplanarPairs) {
  Random rnd(11);
  for (const Real tilt : {1e-9, 1e-6, 1e-3}) {
    FamilyStats s;
    for (int i = 0; i < 5000; ++i) {
      const Tri a = rnd.tri();
      const Vec3 n = normal_of(a);
      Tri b;
      for (Vec3& v : b) {
        const Vec3 in_plane = a[0] + 1.5 * rnd.vec();
        v = in_plane - n.dot(in_plane - a[0]) * n + tilt * rnd.uniform() * n;
      }
      check_pair(a, b, s);
    }
    report(tilt == 1e-9 ? "nearly coplanar 1e-9" : tilt == 1e-6 ? "nearly coplanar 1e-6"
                                                                  : "nearly coplanar 1e-3",
           s);
    EXPECT_EQ(s.non_finite, 0);
    EXPECT_EQ(s.mismatches, 0);
    // The trace ends are interpolated along edges that meet the other plane at angle ~tilt:
    // their error grows like ε/tilt, so the bound is looser for the flattest pairs.
    EXPECT_LT(s.worst_off, tilt < 1e-8 ? 1e-5 : 1e-9);
    EXPECT_GT(s.intersecting, 500);
  }
}

// 2-D reference for triangles in z = 0: they overlap iff a vertex of one lies in the other or
// two edges cross (orient2d signs). margin = the smallest |orient2d| / L².
Real orient2(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}
bool ref_coplanar(const Tri& a, const Tri& b, Real& margin) {
  const Real size = pair_size(a, b);
  margin = 1e300;
  const auto note = [&](Real o) {
    margin = std::min(margin, std::abs(o) / (size * size));
    return o;
  };
  const auto inside = [&](const Tri& t, const Vec3& p) {
    const Real o0 = note(orient2(t[0], t[1], p));
    const Real o1 = note(orient2(t[1], t[2], p));
    const Real o2 = note(orient2(t[2], t[0], p));
    return (o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0);
  };
  bool hit = false;
  for (int k = 0; k < 3; ++k) {
    hit |= inside(b, a[k]);
    hit |= inside(a, b[k]);
    for (int j = 0; j < 3; ++j) {
      const Vec3 &p = a[k], &q = a[(k + 1) % 3], &u = b[j], &v = b[(j + 1) % 3];
      const Real o1 = note(orient2(p, q, u)), o2 = note(orient2(p, q, v));
      const Real o3 = note(orient2(u, v, p)), o4 = note(orient2(u, v, q));
      hit |= (o1 > 0) != (o2 > 0) && (o3 > 0) != (o4 > 0);
    }
  }
  return hit;
}

TEST(TriTriRandom, CoplanarPairsAgreeWithA2DReference) {
  Random rnd(12);
  for (const bool rotate : {false, true}) {
    FamilyStats s;
    int not_flagged = 0;
    for (int i = 0; i < 5000; ++i) {
      Tri a, b;
      for (Vec3& v : a) v = Vec3(rnd.uniform(), rnd.uniform(), 0);
      for (Vec3& v : b) v = Vec3(rnd.uniform(), rnd.uniform(), 0) + Vec3(0.8, 0.3, 0);
      Real margin = 0;
      const bool expected = ref_coplanar(a, b, margin);
      if (rotate) {
        // The same pair after a rigid motion: coplanar only up to rounding.
        const Mat3 rot = (Eigen::AngleAxisd(rnd.uniform(0, 3), rnd.unit())).toRotationMatrix();
        const Vec3 t = rnd.vec(-10, 10);
        for (Vec3& v : a) v = rot * v + t;
        for (Vec3& v : b) v = rot * v + t;
      }
      const TriTriResult r = run(a, b);
      ++s.pairs;
      if (!finite(r)) ++s.non_finite;
      if (r.intersects) ++s.intersecting;
      if (!r.coplanar) ++not_flagged;
      s.worst_off = std::max(s.worst_off, off_both(r, a, b) / pair_size(a, b));
      if (margin > 1e-9) {
        ++s.conditioned;
        if (r.intersects != expected) ++s.mismatches;
      }
    }
    report(rotate ? "coplanar rotated" : "coplanar z=0", s);
    EXPECT_EQ(s.non_finite, 0);
    EXPECT_EQ(s.mismatches, 0);
    EXPECT_EQ(not_flagged, 0);
    // Proper overlaps are clipped exactly; touching pairs come from the widened clip, whose
    // corners may sit a few tolerances (1e-12·L each) outside a triangle with a sharp angle.
    EXPECT_LT(s.worst_off, 1e-10);
    EXPECT_GT(s.intersecting, 500);
    EXPECT_GT(s.conditioned, 4900);
  }
}

TEST(TriTriRandom, SharedVertexAndSharedEdge) {
  Random rnd(13);
  FamilyStats sv;
  int edge_wrong = 0;
  for (int i = 0; i < 5000; ++i) {
    const Tri a = rnd.tri();
    // Shared vertex: always touching, and the segment stays on both triangles.
    const Tri b = {a[0], rnd.vec(), rnd.vec()};
    const TriTriResult r = run(a, b);
    EXPECT_TRUE(r.intersects);
    check_pair(a, b, sv, false);
    // Shared edge, folded: the intersection is exactly the shared edge.
    const Tri c = {a[1], a[0], rnd.vec()};
    const TriTriResult e = run(a, c);
    const Real size = pair_size(a, c);
    const bool ok = e.intersects && !e.coplanar &&
                    (((e.p - a[0]).norm() < 1e-12 * size && (e.q - a[1]).norm() < 1e-12 * size) ||
                     ((e.p - a[1]).norm() < 1e-12 * size && (e.q - a[0]).norm() < 1e-12 * size));
    if (!ok) ++edge_wrong;
  }
  report("shared vertex", sv);
  EXPECT_EQ(sv.non_finite, 0);
  EXPECT_EQ(sv.intersecting, sv.pairs);
  EXPECT_LT(sv.worst_off, 1e-12);
  EXPECT_EQ(edge_wrong, 0);
}

TEST(TriTriRandom, TinyTrianglesOnAndOffALargeOne) {
  Random rnd(14);
  FamilyStats on, off;
  for (int i = 0; i < 5000; ++i) {
    const Tri a = rnd.tri();
    const Vec3 c = rnd.point_in(a, 0.05);  // well inside A
    // Tiny B (size 1e-7) with its centroid on A: it always crosses A.
    Tri b;
    const Vec3 d0 = 1e-7 * rnd.vec(), d1 = 1e-7 * rnd.vec();
    b = {c + d0, c + d1, c - d0 - d1};
    check_pair(a, b, on, false);
    // The same tiny triangle moved 1e-5 off A's plane (100 times its size): apart.
    const Vec3 lift = 1e-5 * normal_of(a);
    const Tri b_off = {b[0] + lift, b[1] + lift, b[2] + lift};
    check_pair(a, b_off, off, false);
  }
  report("tiny on", on);
  report("tiny off", off);
  EXPECT_EQ(on.non_finite + off.non_finite, 0);
  EXPECT_EQ(on.intersecting, on.pairs);
  EXPECT_EQ(off.intersecting, 0);
  EXPECT_LT(on.worst_off, 1e-12);
}

TEST(TriTriRandom, SliversAndDegenerateTrianglesActLikeTheirLongEdge) {
  // A sliver (height 1e-10 of its length), a collinear triangle and one with a repeated vertex,
  // all spanning segment s0s1, against a random triangle B: where the reference test of the
  // segment s0s1 against B is well-conditioned, the answer agrees, and P, Q are within 1e-8·L
  // of the reference piercing point.
  Random rnd(15);
  for (int kind = 0; kind < 3; ++kind) {
    FamilyStats s;
    int far = 0;
    for (int i = 0; i < 5000; ++i) {
      const Vec3 s0 = rnd.vec(), s1 = rnd.vec();
      Tri a;
      if (kind == 0) a = {s0, s1, 0.5 * (s0 + s1) + 1e-10 * rnd.vec()};
      if (kind == 1) a = {s0, s1, s0 + rnd.uniform(0, 1) * (s1 - s0)};
      if (kind == 2) a = {s0, s1, s1};
      const Tri b = rnd.tri();
      const TriTriResult r = run(a, b);
      ++s.pairs;
      if (!finite(r)) ++s.non_finite;
      if (r.intersects) ++s.intersecting;
      s.worst_off = std::max(s.worst_off, off_both(r, a, b) / pair_size(a, b));
      const Real size = pair_size(a, b);
      const RefHit h = ref_segment_triangle(s0, s1, b, size * size * size);
      if (h.margin > 1e-6) {
        ++s.conditioned;
        if (h.hit != r.intersects) ++s.mismatches;
        if (h.hit && r.intersects &&
            std::max((r.p - h.point).norm(), (r.q - h.point).norm()) > 1e-8 * size) {
          ++far;
        }
      }
    }
    report(kind == 0 ? "sliver 1e-10" : kind == 1 ? "collinear" : "repeated vertex", s);
    EXPECT_EQ(s.non_finite, 0);
    EXPECT_EQ(s.mismatches, 0);
    EXPECT_EQ(far, 0);
    EXPECT_LT(s.worst_off, 1e-9);
    EXPECT_GT(s.conditioned, 4500);
    EXPECT_GT(s.intersecting, 200);
  }
}

}  // namespace
}  // namespace trocar
