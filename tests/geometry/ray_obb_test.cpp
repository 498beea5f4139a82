#include "trocar/geometry/ray_obb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace trocar {
namespace {

// Box centred at (1, 2, 3), turned 45° about z: a0 = (1,1,0)/√2, a1 = (−1,1,0)/√2, a2 = z;
// half-extents (2, 1, 0.5).
Obb rotated_box() {
  Obb box;
  box.center = Vec3(1, 2, 3);
  const Real s = 1.0 / std::sqrt(2.0);
  box.axes.col(0) = Vec3(s, s, 0);
  box.axes.col(1) = Vec3(-s, s, 0);
  box.axes.col(2) = Vec3(0, 0, 1);
  box.half_extents = Vec3(2, 1, 0.5);
  return box;
}

TEST(RayObb, FromTheCentreAlongEachAxisExitsAtTheHalfExtent) {
  const Obb box = rotated_box();
  for (int k = 0; k < 3; ++k) {
    for (const Real sign : {1.0, -1.0}) {
      const Vec3 d = sign * box.axes.col(k);
      const RayObbHit h = intersect_ray_obb(box, box.center, d);
      ASSERT_TRUE(h.hit);
      EXPECT_TRUE(h.origin_inside);
      EXPECT_EQ(h.t_entry, 0.0);
      EXPECT_NEAR(h.t_exit, box.half_extents[k], 1e-14);
      EXPECT_NEAR((h.exit - (box.center + box.half_extents[k] * d)).norm(), 0.0, 1e-14);
    }
  }
}

TEST(RayObb, WorldXDirectionLeavesThroughTheNarrowSlab) {
  // d = x = (a0 − a1)/√2: local direction (1/√2, −1/√2, 0). Slab 0 is left at t = 2√2,
  // slab 1 at t = 1/(1/√2) = √2, so the exit is at t = √2, point c + (√2, 0, 0).
  const Obb box = rotated_box();
  const RayObbHit h = intersect_ray_obb(box, box.center, Vec3(3, 0, 0));  // length ignored
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t_exit, std::sqrt(2.0), 1e-14);
  EXPECT_NEAR((h.exit - Vec3(1 + std::sqrt(2.0), 2, 3)).norm(), 0.0, 1e-14);
}

TEST(RayObb, OffCentreInsideOrigin) {
  // P = c + 0.5·a0 + 0.25·a2 along −a2: the z slab is left after 0.5 + 0.25 = 0.75.
  const Obb box = rotated_box();
  const Vec3 p = box.center + 0.5 * box.axes.col(0) + 0.25 * box.axes.col(2);
  const RayObbHit h = intersect_ray_obb(box, p, -box.axes.col(2));
  ASSERT_TRUE(h.hit);
  EXPECT_TRUE(h.origin_inside);
  EXPECT_NEAR(h.t_exit, 0.75, 1e-14);
  // Along a0 from the same point: 2 − 0.5 = 1.5.
  EXPECT_NEAR(intersect_ray_obb(box, p, box.axes.col(0)).t_exit, 1.5, 1e-14);
}

TEST(RayObb, OutsideOriginGivesEntryAndExitOrMiss) {
  const Obb box = rotated_box();
  const Vec3 a0 = box.axes.col(0);
  // 5 behind the centre along a0: enters at 5 − 2 = 3, leaves at 5 + 2 = 7.
  const RayObbHit h = intersect_ray_obb(box, box.center - 5 * a0, a0);
  ASSERT_TRUE(h.hit);
  EXPECT_FALSE(h.origin_inside);
  EXPECT_NEAR(h.t_entry, 3.0, 1e-14);
  EXPECT_NEAR(h.t_exit, 7.0, 1e-14);
  EXPECT_NEAR((h.entry - (box.center - 2 * a0)).norm(), 0.0, 1e-14);
  // Pointing away: miss.
  EXPECT_FALSE(intersect_ray_obb(box, box.center - 5 * a0, -a0).hit);
  // Parallel to a slab and outside it (above the top face, moving along a0): miss, no NaN.
  const RayObbHit m = intersect_ray_obb(box, box.center + Vec3(0, 0, 1), a0);
  EXPECT_FALSE(m.hit);
  EXPECT_TRUE(m.exit.allFinite());
  // Zero direction: no ray.
  EXPECT_FALSE(intersect_ray_obb(box, box.center, Vec3::Zero()).hit);
  EXPECT_TRUE(intersect_ray_obb(box, box.center, Vec3::Zero()).origin_inside);
}

TEST(RayObb, OriginOnAFacePointingOutExitsImmediately) {
  const Obb box = rotated_box();
  const Vec3 p = box.center + 0.5 * box.axes.col(2);  // on the top face
  const RayObbHit h = intersect_ray_obb(box, p, box.axes.col(2));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t_exit, 0.0, 1e-14);
  EXPECT_GE(h.t_exit, 0.0);
}

TEST(RayObb, RandomInsideRaysExitOnTheSurface) {
  // Property check: from random inside points along random directions, the exit point lies on
  // the box surface (largest |local coordinate| / half-extent = 1) and t_exit = |exit − P|.
  const Obb box = rotated_box();
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 local(u(rng) * 2, u(rng) * 1, u(rng) * 0.5);
    const Vec3 p = box.center + box.axes * local;
    const Vec3 d(u(rng), u(rng), u(rng));
    const RayObbHit h = intersect_ray_obb(box, p, d);
    ASSERT_TRUE(h.hit);
    ASSERT_TRUE(h.origin_inside);
    const Vec3 e = box.to_local(h.exit).cwiseAbs().cwiseQuotient(box.half_extents);
    EXPECT_NEAR(e.maxCoeff(), 1.0, 1e-12);
    EXPECT_NEAR((h.exit - p).norm(), h.t_exit, 1e-12);
    EXPECT_NEAR((h.exit - p).normalized().dot(d.normalized()), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace trocar
