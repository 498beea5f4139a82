// Hand-computed cases for intersect_triangles. Triangle A is mostly the right triangle
// (0,0,0), (2,0,0), (0,2,0) in the plane z = 0 (x ≥ 0, y ≥ 0, x + y ≤ 2).
#include "trocar/geometry/triangle_triangle.h"

#include <gtest/gtest.h>

#include <limits>

namespace trocar {
namespace {

const Vec3 kA0(0, 0, 0);
const Vec3 kA1(2, 0, 0);
const Vec3 kA2(0, 2, 0);

// True when {p, q} equals {e, f} as an unordered pair, within tol.
bool same_segment(const TriTriResult& r, const Vec3& e, const Vec3& f, Real tol = 1e-14) {
  return ((r.p - e).norm() <= tol && (r.q - f).norm() <= tol) ||
         ((r.p - f).norm() <= tol && (r.q - e).norm() <= tol);
}

// Calls the test with both argument orders (the result must be symmetric).
TriTriResult both_orders(const Vec3& b0, const Vec3& b1, const Vec3& b2, const Vec3& a0 = kA0,
                         const Vec3& a1 = kA1, const Vec3& a2 = kA2) {
  const TriTriResult ab = intersect_triangles(a0, a1, a2, b0, b1, b2);
  const TriTriResult ba = intersect_triangles(b0, b1, b2, a0, a1, a2);
  EXPECT_EQ(ab.intersects, ba.intersects);
  EXPECT_EQ(ab.coplanar, ba.coplanar);
  if (ab.intersects && ba.intersects) {
    EXPECT_TRUE(same_segment(ba, ab.p, ab.q, 1e-13))
        << ab.p.transpose() << " | " << ab.q.transpose() << " vs " << ba.p.transpose() << " | "
        << ba.q.transpose();
  }
  return ab;
}

TEST(TriTri, ProperCrossingGivesTheOverlapOfBothTraces) {
  // B stands in the plane y = 0.5. B's trace on z = 0: edge (0.25,.5,−1)→(1,.5,1) crosses at its
  // midpoint (0.625, 0.5, 0), edge (1,.5,1)→(1,.5,−1) at (1, 0.5, 0). A's trace on y = 0.5 runs
  // from x = 0 to x = 1.5 (x + y ≤ 2). Overlap: (0.625,0.5,0)–(1,0.5,0).
  const TriTriResult r =
      both_orders(Vec3(0.25, 0.5, -1), Vec3(1, 0.5, 1), Vec3(1, 0.5, -1));
  ASSERT_TRUE(r.intersects);
  EXPECT_FALSE(r.coplanar);
  EXPECT_TRUE(same_segment(r, Vec3(0.625, 0.5, 0), Vec3(1, 0.5, 0)));
}

TEST(TriTri, PiercingWholeWidth) {
  // B in the plane x = 0.5, large enough to cut A across: A's trace on x = 0.5 is y ∈ [0, 1.5];
  // B covers y ∈ [−5, 5] at z = 0, so the segment is (0.5,0,0)–(0.5,1.5,0).
  const TriTriResult r = both_orders(Vec3(0.5, -5, -1), Vec3(0.5, 5, -1), Vec3(0.5, 0, 10));
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(same_segment(r, Vec3(0.5, 0, 0), Vec3(0.5, 1.5, 0)));
}

TEST(TriTri, SeparatedAndPlaneCrossingButDisjoint) {
  EXPECT_FALSE(both_orders(Vec3(0.25, 0.5, 4), Vec3(1, 0.5, 6), Vec3(1, 0.5, 4)).intersects);
  // B crosses z = 0 at x ∈ [3, 4] on y = 0.5, outside A (x ≤ 1.5 there).
  EXPECT_FALSE(both_orders(Vec3(3, 0.5, -1), Vec3(4, 0.5, 1), Vec3(4, 0.5, -1)).intersects);
}

TEST(TriTri, VertexTouchingTheInteriorIsAPoint) {
  const TriTriResult r = both_orders(Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 1), Vec3(1, 0.5, 1));
  ASSERT_TRUE(r.intersects);
  EXPECT_EQ(r.p, Vec3(0.5, 0.5, 0));
  EXPECT_EQ(r.q, Vec3(0.5, 0.5, 0));
  // Lifted by 1e-6 it no longer touches.
  EXPECT_FALSE(both_orders(Vec3(0.5, 0.5, 1e-6), Vec3(0.5, 0.5, 1), Vec3(1, 0.5, 1)).intersects);
}

TEST(TriTri, EdgeLyingInThePlaneAcrossAnEdge) {
  // B in the plane x = 1 with its edge (1,−0.5,0)–(1,0.5,0) in z = 0. A's trace on x = 1 is
  // y ∈ [0, 1]; overlap y ∈ [0, 0.5].
  const TriTriResult r = both_orders(Vec3(1, -0.5, 0), Vec3(1, 0.5, 0), Vec3(1, 0, 1));
  ASSERT_TRUE(r.intersects);
  EXPECT_FALSE(r.coplanar);
  EXPECT_TRUE(same_segment(r, Vec3(1, 0, 0), Vec3(1, 0.5, 0)));
}

TEST(TriTri, VertexOnAnEdgeIsAPoint) {
  // B's vertex (1,0,0) sits on A's edge y = 0; B rises into z > 0 only.
  const TriTriResult r = both_orders(Vec3(1, 0, 0), Vec3(1, -1, 1), Vec3(1, 1, 1));
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(same_segment(r, Vec3(1, 0, 0), Vec3(1, 0, 0)));
}

TEST(TriTri, SharedVertexOnly) {
  // B shares A's vertex (2,0,0) and otherwise lies above z = 0.
  const TriTriResult r = both_orders(Vec3(2, 0, 0), Vec3(3, 1, 1), Vec3(3, -1, 2));
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(same_segment(r, kA1, kA1));
}

TEST(TriTri, SharedEdgeFoldedIsTheEdge) {
  // Two faces of a tent sharing the edge (0,0,0)–(2,0,0).
  const TriTriResult r = both_orders(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, -1, 1));
  ASSERT_TRUE(r.intersects);
  EXPECT_FALSE(r.coplanar);
  EXPECT_TRUE(same_segment(r, kA0, kA1));
}

TEST(TriTri, CoplanarOverlapReturnsTheLongestChord) {
  // B: x ≥ 0.5, y ≥ 0.5, x + y ≤ 3.5. Overlap with A: x ≥ 0.5, y ≥ 0.5, x + y ≤ 2, the triangle
  // (0.5,0.5), (1.5,0.5), (0.5,1.5); its longest chord is the hypotenuse (1.5,0.5)–(0.5,1.5).
  const TriTriResult r = both_orders(Vec3(0.5, 0.5, 0), Vec3(3, 0.5, 0), Vec3(0.5, 3, 0));
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(r.coplanar);
  EXPECT_TRUE(same_segment(r, Vec3(1.5, 0.5, 0), Vec3(0.5, 1.5, 0)));
}

TEST(TriTri, CoplanarContainedTriangleIsItsOwnLongestEdge) {
  // B inside A: chord = B's longest edge (0.2,0.2)–(1.0,0.2) (length 0.8 > √0.52 and √0.2).
  const TriTriResult r = both_orders(Vec3(0.2, 0.2, 0), Vec3(1.0, 0.2, 0), Vec3(0.4, 0.6, 0));
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(r.coplanar);
  EXPECT_TRUE(same_segment(r, Vec3(0.2, 0.2, 0), Vec3(1.0, 0.2, 0)));
}

TEST(TriTri, CoplanarTouchingAlongAnEdgeAndAtAVertex) {
  // B on the other side of the hypotenuse x + y = 2: they share exactly that edge.
  const TriTriResult e = both_orders(Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0));
  ASSERT_TRUE(e.intersects);
  EXPECT_TRUE(e.coplanar);
  EXPECT_TRUE(same_segment(e, kA1, kA2));
  // B touching at the corner (2,0,0) only.
  const TriTriResult v = both_orders(Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(3, -1, 0));
  ASSERT_TRUE(v.intersects);
  EXPECT_TRUE(same_segment(v, kA1, kA1, 2e-11));
  // Coplanar and apart.
  const TriTriResult f = both_orders(Vec3(5, 0, 0), Vec3(6, 0, 0), Vec3(5, 1, 0));
  EXPECT_FALSE(f.intersects);
  EXPECT_TRUE(f.coplanar);
}

TEST(TriTri, DegenerateCollinearTrianglePiercingIsAPoint) {
  // B lies in the plane x = 1; in (y, z) its vertices are (−1,−1), (2,−1), (0.5,2), and at z = 0
  // it spans y ∈ [−0.5, 1.5], so it contains (1, 0.5, 0). A is the segment (0,0.5,0)–(2,0.5,0)
  // written as a degenerate triangle three ways (repeated vertex twice, collinear midpoint);
  // the segment pierces B at x = 1.
  const Vec3 b0(1, -1, -1), b1(1, 2, -1), b2(1, 0.5, 2);
  const Vec3 s0(0, 0.5, 0), s1(2, 0.5, 0);
  for (const auto& tri : {std::array<Vec3, 3>{s0, s1, s1}, std::array<Vec3, 3>{s0, s0, s1},
                          std::array<Vec3, 3>{s0, s1, Vec3(1, 0.5, 0)}}) {
    const TriTriResult r = both_orders(b0, b1, b2, tri[0], tri[1], tri[2]);
    ASSERT_TRUE(r.intersects);
    EXPECT_FALSE(r.coplanar);
    EXPECT_TRUE(same_segment(r, Vec3(1, 0.5, 0), Vec3(1, 0.5, 0)));
  }
}

TEST(TriTri, DegenerateSegmentInThePlaneIsClipped) {
  // A collinear along y = 0.5 in z = 0 from x = −1 to 3 against the standard A (renamed B
  // here): inside for x ∈ [0, 1.5].
  const TriTriResult r =
      both_orders(Vec3(-1, 0.5, 0), Vec3(3, 0.5, 0), Vec3(1, 0.5, 0));
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(r.coplanar);
  EXPECT_TRUE(same_segment(r, Vec3(0, 0.5, 0), Vec3(1.5, 0.5, 0)));
}

TEST(TriTri, DegeneratePointTriangles) {
  const Vec3 p(0.5, 0.5, 0);
  const TriTriResult in = both_orders(p, p, p);
  ASSERT_TRUE(in.intersects);
  EXPECT_TRUE(same_segment(in, p, p));
  EXPECT_FALSE(both_orders(Vec3(0.5, 0.5, 0.1), Vec3(0.5, 0.5, 0.1), Vec3(0.5, 0.5, 0.1))
                   .intersects);
  EXPECT_FALSE(both_orders(Vec3(3, 3, 0), Vec3(3, 3, 0), Vec3(3, 3, 0)).intersects);
}

TEST(TriTri, DegenerateSegmentsCrossingAndCollinear) {
  // Two segments crossing at (1,0,0).
  const TriTriResult x = both_orders(Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(1, 1, 0),
                                     Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0));
  ASSERT_TRUE(x.intersects);
  EXPECT_TRUE(same_segment(x, Vec3(1, 0, 0), Vec3(1, 0, 0)));
  // Collinear, overlapping on x ∈ [1, 2].
  const TriTriResult c = both_orders(Vec3(1, 0, 0), Vec3(5, 0, 0), Vec3(3, 0, 0),
                                     Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 0, 0));
  ASSERT_TRUE(c.intersects);
  EXPECT_TRUE(same_segment(c, Vec3(1, 0, 0), Vec3(2, 0, 0)));
  // Skew, 0.1 apart.
  EXPECT_FALSE(both_orders(Vec3(1, -1, 0.1), Vec3(1, 1, 0.1), Vec3(1, 1, 0.1), Vec3(0, 0, 0),
                           Vec3(2, 0, 0), Vec3(1, 0, 0))
                   .intersects);
}

TEST(TriTri, FarFromTheOriginKeepsTheRelativeAccuracy) {
  // The first case shifted by (1e6, −1e6, 1e6): same segment, shifted.
  const Vec3 s(1e6, -1e6, 1e6);
  const TriTriResult r = intersect_triangles(kA0 + s, kA1 + s, kA2 + s, Vec3(0.25, 0.5, -1) + s,
                                             Vec3(1, 0.5, 1) + s, Vec3(1, 0.5, -1) + s);
  ASSERT_TRUE(r.intersects);
  EXPECT_TRUE(same_segment(r, Vec3(0.625, 0.5, 0) + s, Vec3(1, 0.5, 0) + s, 1e-9));
}

TEST(TriTri, NonFiniteInputIsNoIntersectionAndNoNaN) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  for (const Real bad : {nan, inf}) {
    const TriTriResult r =
        intersect_triangles(kA0, kA1, kA2, Vec3(bad, 0, 0), Vec3(1, 0.5, 1), Vec3(1, 0.5, -1));
    EXPECT_FALSE(r.intersects);
    EXPECT_TRUE(r.p.allFinite() && r.q.allFinite());
  }
}

}  // namespace
}  // namespace trocar
