#include "trocar/geometry/closest_point.h"

#include <gtest/gtest.h>

#include <random>

namespace trocar {
namespace {

const Vec3 kA(0, 0, 0);
const Vec3 kB(1, 0, 0);
const Vec3 kC(0, 1, 0);

void expect_closest(const Vec3& p, const Vec3& expected, TriangleFeature feature, int index) {
  const TriangleClosestPoint r = closest_point_on_triangle(p, kA, kB, kC);
  EXPECT_NEAR((r.point - expected).norm(), 0.0, 1e-15) << "p = " << p.transpose();
  EXPECT_EQ(r.feature, feature) << "p = " << p.transpose();
  EXPECT_EQ(r.index, index) << "p = " << p.transpose();
  EXPECT_NEAR((r.barycentric[0] * kA + r.barycentric[1] * kB + r.barycentric[2] * kC - r.point)
                  .norm(), 0.0, 1e-15);
}

TEST(ClosestPointOnTriangle, EveryVoronoiRegionOfTheUnitRightTriangle) {
  // Face: straight down from above.
  expect_closest(Vec3(0.25, 0.25, 2), Vec3(0.25, 0.25, 0), TriangleFeature::kFace, 0);
  // Edge 0 (A→B, y = 0): (0.5, −1, 0) drops to (0.5, 0, 0).
  expect_closest(Vec3(0.5, -1, 0.3), Vec3(0.5, 0, 0), TriangleFeature::kEdge, 0);
  // Edge 1 (B→C, x + y = 1): (1, 1, 0) projects along (1,1)/√2 to (0.5, 0.5, 0).
  expect_closest(Vec3(1, 1, 0), Vec3(0.5, 0.5, 0), TriangleFeature::kEdge, 1);
  // Edge 2 (C→A, x = 0): (−1, 0.5, 0) drops to (0, 0.5, 0).
  expect_closest(Vec3(-1, 0.5, 0), Vec3(0, 0.5, 0), TriangleFeature::kEdge, 2);
  // Vertex regions: behind A in both edge directions; beyond B along x; beyond C along y.
  expect_closest(Vec3(-1, -1, 1), kA, TriangleFeature::kVertex, 0);
  expect_closest(Vec3(2, -0.5, 0), kB, TriangleFeature::kVertex, 1);
  expect_closest(Vec3(-0.5, 3, -1), kC, TriangleFeature::kVertex, 2);
}

TEST(ClosestPointOnTriangle, AgreesWithDenseSamplingOnARandomTriangle) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    const TriangleClosestPoint r = closest_point_on_triangle(p, a, b, c);
    const Real d = (p - r.point).norm();
    // No sample of the triangle is closer (a 200×200 barycentric grid).
    Real best = 1e300;
    for (int i = 0; i <= 200; ++i) {
      for (int j = 0; i + j <= 200; ++j) {
        const Vec3 x = a + (b - a) * (i / 200.0) + (c - a) * (j / 200.0);
        best = std::min(best, (p - x).norm());
      }
    }
    EXPECT_LE(d, best + 1e-12);
    EXPECT_GE(d, best - 0.02);  // grid spacing ≤ 0.02 here
  }
}

TEST(ClosestPointOnTriangle, DegenerateTrianglesGiveFinitePointsOnTheSegment) {
  // Collinear a = 0, b = 2, c = 1 on x: (1.5, 1, 0) → (1.5, 0, 0) at distance 1.
  const TriangleClosestPoint r =
      closest_point_on_triangle(Vec3(1.5, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0));
  EXPECT_TRUE(r.point.allFinite());
  EXPECT_NEAR((r.point - Vec3(1.5, 0, 0)).norm(), 0.0, 1e-15);
  // All three vertices equal.
  const Vec3 v(1, 2, 3);
  const TriangleClosestPoint s = closest_point_on_triangle(Vec3(0, 0, 0), v, v, v);
  EXPECT_EQ(s.point, v);
  EXPECT_TRUE(s.barycentric.allFinite());
  // Two equal vertices: a = b = 0, c = (0, 2, 0); (1, 1, 0) → (0, 1, 0).
  const TriangleClosestPoint t =
      closest_point_on_triangle(Vec3(1, 1, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 2, 0));
  EXPECT_NEAR((t.point - Vec3(0, 1, 0)).norm(), 0.0, 1e-15);
}

TEST(ClosestPointsSegmentSegment, CrossingSkewAndParallel) {
  // Skew: x axis segment [−1,1] and a segment along y at z = 2 through x = 0.5 → distance 2,
  // at s = 0.75 and t = 0.5.
  const SegmentSegmentClosest c = closest_points_segment_segment(
      Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 2), Vec3(0.5, 1, 2));
  EXPECT_NEAR(c.s, 0.75, 1e-15);
  EXPECT_NEAR(c.t, 0.5, 1e-15);
  EXPECT_NEAR(c.distance_squared, 4.0, 1e-15);
  // Parallel, offset by 1 in y and overlapping in x: distance 1.
  const SegmentSegmentClosest p = closest_points_segment_segment(
      Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 1, 0), Vec3(3, 1, 0));
  EXPECT_NEAR(p.distance_squared, 1.0, 1e-15);
  // Point against segment.
  const SegmentSegmentClosest q = closest_points_segment_segment(
      Vec3(5, 1, 0), Vec3(5, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0));
  EXPECT_EQ(q.on_q, Vec3(2, 0, 0));
  EXPECT_NEAR(q.distance_squared, 10.0, 1e-15);  // (5−2)² + 1²
}

}  // namespace
}  // namespace trocar
