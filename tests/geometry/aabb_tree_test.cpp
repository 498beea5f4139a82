#include "trocar/geometry/aabb_tree.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace trocar {
namespace {

std::vector<Aabb> random_boxes(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<Real> u(-10, 10);
  std::uniform_real_distribution<Real> s(0, 0.5);
  std::vector<Aabb> boxes;
  for (int i = 0; i < n; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const Vec3 h(s(rng), s(rng), s(rng));
    boxes.push_back({c - h, c + h});
  }
  return boxes;
}

// Every node box holds its subtree; every item appears in exactly one leaf.
void check_structure(const AabbTree& tree, const std::vector<Aabb>& boxes) {
  std::vector<int> seen(boxes.size(), 0);
  const auto nodes = tree.nodes();
  for (const AabbTree::Node& n : nodes) {
    if (n.count > 0) {
      EXPECT_LE(n.count, AabbTree::kLeafSize);
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
        const std::uint32_t item = tree.items()[i];
        ++seen[item];
        EXPECT_TRUE(n.box.contains(boxes[item].min) && n.box.contains(boxes[item].max));
      }
    } else {
      for (const std::uint32_t c : {n.first, n.first + 1}) {
        EXPECT_TRUE(n.box.contains(nodes[c].box.min) && n.box.contains(nodes[c].box.max));
      }
    }
  }
  for (const int s : seen) EXPECT_EQ(s, 1);
}

TEST(AabbTree, BuildRefitAndNearestAgreeWithALinearScan) {
  std::mt19937_64 rng(1);
  std::vector<Aabb> boxes = random_boxes(rng, 1000);
  AabbTree tree(boxes);
  check_structure(tree, boxes);
  // 1000 items, leaves of ≤ 4 from median splits: 2·256 − 1 = 511 nodes.
  EXPECT_EQ(tree.nodes().size(), 511u);

  const auto check_nearest = [&]() {
    std::uniform_real_distribution<Real> u(-12, 12);
    for (int i = 0; i < 200; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng));
      Real best = std::numeric_limits<Real>::infinity();
      tree.nearest(p, best, [&](std::uint32_t item, Real& b) {
        b = std::min(b, AabbTree::distance_squared(boxes[item], p));
      });
      Real expected = std::numeric_limits<Real>::infinity();
      for (const Aabb& box : boxes) expected = std::min(expected, AabbTree::distance_squared(box, p));
      EXPECT_EQ(best, expected);
    }
  };
  check_nearest();
  for (Aabb& b : boxes) {  // move everything
    const Vec3 shift(std::sin(b.min.x()), std::cos(b.min.y()), 0.3 * b.min.z());
    b.min += shift;
    b.max += shift;
  }
  tree.refit(boxes);
  check_structure(tree, boxes);
  check_nearest();
  EXPECT_THROW(tree.refit(std::span<const Aabb>(boxes).first(3)), std::exception);
}

TEST(AabbTree, EmptyAndSingle) {
  AabbTree empty(std::span<const Aabb>{});
  EXPECT_TRUE(empty.empty());
  Real best = 5;
  empty.nearest(Vec3::Zero(), best, [](std::uint32_t, Real&) { FAIL(); });
  EXPECT_EQ(best, 5);
  const std::vector<Aabb> one = {Aabb{Vec3(1, 1, 1), Vec3(2, 2, 2)}};
  AabbTree single(one);
  ASSERT_EQ(single.nodes().size(), 1u);
  EXPECT_EQ(AabbTree::distance_squared(one[0], Vec3(0, 0, 0)), 3.0);  // (1,1,1) away
}

}  // namespace
}  // namespace trocar
