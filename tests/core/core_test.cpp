#include <gtest/gtest.h>
#include <atomic>

#include <numbers>
#include <random>
#include <thread>

#include "trocar/core/aabb.h"
#include "trocar/core/error.h"
#include "trocar/core/obb.h"
#include "trocar/core/pose.h"
#include "trocar/core/triple_buffer.h"

namespace trocar {
namespace {

TEST(Aabb, EmptyGrowsAndOverlaps) {
  Aabb box;
  EXPECT_TRUE(box.is_empty());
  EXPECT_EQ(box.diagonal(), 0.0);
  box.expand(Vec3(1, 2, 3));
  box.expand(Vec3(-1, 0, 5));
  EXPECT_FALSE(box.is_empty());
  EXPECT_EQ(box.min, Vec3(-1, 0, 3));
  EXPECT_EQ(box.max, Vec3(1, 2, 5));
  EXPECT_DOUBLE_EQ(box.diagonal(), std::sqrt(4.0 + 4.0 + 4.0));
  EXPECT_TRUE(box.overlaps(Aabb{Vec3(1, 2, 5), Vec3(9, 9, 9)}));  // touching corner counts
  EXPECT_FALSE(box.overlaps(Aabb{Vec3(1.01, 0, 3), Vec3(9, 9, 9)}));
  EXPECT_TRUE(box.intersection(Aabb{Vec3(2, 0, 0), Vec3(3, 1, 1)}).is_empty());
  EXPECT_EQ(box.inflated(0.5).min, Vec3(-1.5, -0.5, 2.5));
}

TEST(Obb, PcaOfABoxRecoversItsAxesAndExtents) {
  // Corners of a 4 × 2 × 1 box rotated 30° about z and moved: PCA must find the same box.
  const Pose pose = Pose::from_euler_deg(Vec3(1, -2, 3), Vec3(0, 0, 30));
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i)
    points.push_back(pose.apply(Vec3((i & 1) ? 2 : -2, (i & 2) ? 1 : -1, (i & 4) ? 0.5 : -0.5)));
  const Obb box = Obb::fit_pca(points);
  EXPECT_NEAR((box.center - Vec3(1, -2, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR(box.half_extents.x(), 2.0, 1e-12);
  EXPECT_NEAR(box.half_extents.y(), 1.0, 1e-12);
  EXPECT_NEAR(box.half_extents.z(), 0.5, 1e-12);
  const Vec3 long_axis = pose.apply_vector(Vec3::UnitX());
  EXPECT_NEAR(std::abs(box.axes.col(0).dot(long_axis)), 1.0, 1e-12);
  EXPECT_NEAR(box.axes.determinant(), 1.0, 1e-12);
  EXPECT_NEAR(box.volume(), 8.0, 1e-10);
}

TEST(Obb, ContainsEveryPointOfARandomCloud) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, 1);
  std::vector<Vec3> points;
  for (int i = 0; i < 2000; ++i) points.emplace_back(5 * n(rng), n(rng), 0.2 * n(rng) + n(rng));
  const Obb box = Obb::fit_pca(points);
  for (const Vec3& p : points) EXPECT_TRUE(box.contains(p, 1e-9));
  EXPECT_FALSE(box.contains(box.center + box.axes.col(0) * (box.half_extents.x() + 1e-3)));
  const Aabb aabb = box.bounds();
  for (const Vec3& c : box.corners()) EXPECT_TRUE(aabb.contains(c) || aabb.inflated(1e-9).contains(c));
}

TEST(Obb, DegenerateInputsGiveFiniteBoxes) {
  EXPECT_EQ(Obb::fit_pca({}).half_extents, Vec3::Zero());
  const std::vector<Vec3> one{Vec3(1, 2, 3)};
  const Obb single = Obb::fit_pca(one);
  EXPECT_TRUE(single.axes.allFinite());
  EXPECT_EQ(single.center, Vec3(1, 2, 3));
  const std::vector<Vec3> line{Vec3(0, 0, 0), Vec3(0, 0, 2), Vec3(0, 0, 1)};
  const Obb seg = Obb::fit_pca(line);
  EXPECT_NEAR(seg.half_extents.x(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(seg.axes.col(0).z()), 1.0, 1e-12);
}

TEST(Pose, EulerConventionIsZYXAboutFixedAxes) {
  // Rx(90) takes y to z; then Rz(90) takes z to z. So y → z.
  const Pose p = Pose::from_euler_deg(Vec3::Zero(), Vec3(90, 0, 90));
  EXPECT_NEAR((p.apply(Vec3::UnitY()) - Vec3::UnitZ()).norm(), 0, 1e-15);
  // x: Rx leaves it, Rz(90) takes it to y.
  EXPECT_NEAR((p.apply(Vec3::UnitX()) - Vec3::UnitY()).norm(), 0, 1e-15);
}

TEST(Pose, InverseAndCompose) {
  const Pose a = Pose::from_euler_deg(Vec3(1, 2, 3), Vec3(10, 20, 30));
  const Pose b = Pose::from_euler_deg(Vec3(-4, 0, 1), Vec3(-50, 5, 70));
  const Vec3 x(0.3, -0.7, 2.0);
  EXPECT_NEAR((a.inverse().apply(a.apply(x)) - x).norm(), 0, 1e-14);
  EXPECT_NEAR(((a * b).apply(x) - a.apply(b.apply(x))).norm(), 0, 1e-14);
}

TEST(Pose, TransformedAabbHoldsTheTransformedCorners) {
  const Aabb box{Vec3(-1, -2, -3), Vec3(1, 2, 3)};
  const Pose p = Pose::from_euler_deg(Vec3(5, 0, 0), Vec3(0, 0, 45));
  const Aabb moved = p.apply(box);
  // Rotating 45° about z: x-extent becomes (1 + 2)/√2 each side.
  EXPECT_NEAR(moved.max.x() - 5, 3 / std::numbers::sqrt2, 1e-12);
  EXPECT_NEAR(moved.max.z(), 3, 1e-12);
  const Obb obb = p.apply(Obb{Vec3::Zero(), Mat3::Identity(), Vec3(1, 2, 3)});
  for (const Vec3& c : obb.corners()) EXPECT_TRUE(moved.inflated(1e-12).contains(c));
}

TEST(FileError, MessageNamesFileAndPlace) {
  EXPECT_STREQ(FileError("a.obj", FileLocation::line(12), "bad index").what(),
               "a.obj:12: bad index");
  EXPECT_STREQ(FileError("b.stl", FileLocation::byte(84), "truncated").what(),
               "b.stl: byte 84: truncated");
  EXPECT_STREQ(FileError("c.ply", FileLocation::none(), "empty").what(), "c.ply: empty");
}

}  // namespace
}  // namespace trocar

// core/triple_buffer.h: the reader sees only whole published slots, the newest one.
namespace trocar {
namespace {

TEST(TripleBuffer, ReaderSeesTheNewestWholeSnapshot) {
  TripleBuffer<std::vector<int>> buffer;
  EXPECT_FALSE(buffer.update());
  buffer.back().assign(3, 7);
  buffer.publish();
  buffer.back().assign(3, 8);
  buffer.publish();  // the reader missed 7: it gets the newest
  ASSERT_TRUE(buffer.update());
  EXPECT_EQ(buffer.front(), std::vector<int>(3, 8));
  EXPECT_FALSE(buffer.update());
  // Concurrent: every slot the reader takes is internally consistent and never goes back.
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int i = 1; i <= 200000; ++i) {
      buffer.back().assign(16, i);
      buffer.publish();
    }
    done = true;
  });
  int last = 0;
  while (!done.load()) {
    if (!buffer.update()) continue;
    const std::vector<int>& v = buffer.front();
    ASSERT_EQ(v.size(), 16u);
    for (int x : v) ASSERT_EQ(x, v[0]);
    ASSERT_GE(v[0], last);
    last = v[0];
  }
  writer.join();
  buffer.update();
  EXPECT_EQ(buffer.front()[0], 200000);
}

}  // namespace
}  // namespace trocar

// The test build of scripts/test and CI keeps assert() on (TROCAR_ASSERTS): a Release flag
// that crept back in would silently turn every assertion off.
#if defined(TROCAR_ASSERTS) && defined(NDEBUG)
#error "TROCAR_ASSERTS is on but NDEBUG is defined: the assertions would not run"
#endif
