#include "trocar/geometry/barycentric.h"

#include <gtest/gtest.h>

namespace trocar {
namespace {

const Vec3 kA(0, 0, 0);
const Vec3 kB(1, 0, 0);
const Vec3 kC(0, 1, 0);

TEST(Barycentric, PointAboveTheTriangleProjectsOntoItsPlane) {
  // p = (0.25, 0.5, 3) projects to (0.25, 0.5, 0) = u·A + v·B + w·C with v = x = 0.25,
  // w = y = 0.5, u = 1 − v − w = 0.25; the height 3 does not matter.
  const Vec3 l = barycentric(Vec3(0.25, 0.5, 3), kA, kB, kC);
  EXPECT_NEAR(l[0], 0.25, 1e-15);
  EXPECT_NEAR(l[1], 0.25, 1e-15);
  EXPECT_NEAR(l[2], 0.5, 1e-15);
}

TEST(Barycentric, VerticesAndOutsidePoints) {
  EXPECT_TRUE(barycentric(kB, kA, kB, kC).isApprox(Vec3(0, 1, 0)));
  // (2, −1, 0) = 0·A + 2·B − 1·C, so (u, v, w) = (0, 2, −1).
  const Vec3 l = barycentric(Vec3(2, -1, 0), kA, kB, kC);
  EXPECT_NEAR(l[0], 0.0, 1e-15);
  EXPECT_NEAR(l[1], 2.0, 1e-15);
  EXPECT_NEAR(l[2], -1.0, 1e-15);
}

TEST(Barycentric, ScaledTiltedTriangleReproducesThePoint) {
  // A generic triangle: the weights must reproduce an in-plane point exactly (up to rounding).
  const Vec3 a(1.5, -2, 0.25), b(3, 1, -1), c(-0.5, 2.5, 2);
  const Vec3 p = 0.2 * a + 0.3 * b + 0.5 * c;
  const Vec3 l = barycentric(p, a, b, c);
  EXPECT_NEAR(l[0], 0.2, 1e-14);
  EXPECT_NEAR(l[1], 0.3, 1e-14);
  EXPECT_NEAR(l[2], 0.5, 1e-14);
}

TEST(Barycentric, CollinearTriangleUsesItsLongestEdge) {
  // a = 0, b = 1, c = 4 on the x axis: longest edge is c→a; p = (1, 5, 0) projects to x = 1,
  // parameter from c toward a: t = (1 − 4)/(0 − 4) = 0.75 → weight 0.75 at a, 0.25 at c.
  const Vec3 l = barycentric(Vec3(1, 5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(4, 0, 0));
  EXPECT_TRUE(l.allFinite());
  EXPECT_NEAR(l[0], 0.75, 1e-15);
  EXPECT_NEAR(l[1], 0.0, 1e-15);
  EXPECT_NEAR(l[2], 0.25, 1e-15);
}

TEST(Barycentric, AllVerticesEqualGivesFirstVertex) {
  const Vec3 v(1, 2, 3);
  EXPECT_EQ(barycentric(Vec3(5, 5, 5), v, v, v), Vec3(1, 0, 0));
}

}  // namespace
}  // namespace trocar
