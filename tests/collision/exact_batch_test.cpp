// The narrow phase's vector exact test (narrow_detail::exact4_avx2) against
// intersect_triangles, bit for bit, on every lane it answers: random crossing pairs at all
// scales and offsets, touching and near-parallel ones, mixed with lanes it must leave alone.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/core/cpu_features.h"
#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace {

using Pair = std::array<Vec3, 6>;

// A triangle through a random point of triangle a (so that the pair usually crosses), of a
// random orientation and size; some snapped to a's plane, some with a vertex on it.
Pair random_pair(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> kind(0, 19);
  const double scale = std::pow(10.0, 3 * u(rng));
  const Vec3 offset = Vec3(u(rng), u(rng), u(rng)) * std::pow(10.0, 4 * u(rng));
  Pair p;
  for (int k = 0; k < 3; ++k) p[k] = offset + scale * Vec3(u(rng), u(rng), u(rng));
  const double w0 = std::abs(u(rng)), w1 = std::abs(u(rng)), w2 = std::abs(u(rng));
  const Vec3 x = (w0 * p[0] + w1 * p[1] + w2 * p[2]) / (w0 + w1 + w2 + 1e-300);
  const double size_b = scale * std::pow(10.0, u(rng));
  for (int k = 3; k < 6; ++k) p[k] = x + size_b * Vec3(u(rng), u(rng), u(rng));
  const int what = kind(rng);
  const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
  if (what == 0) {  // coplanar
    for (int k = 3; k < 6; ++k) p[k] -= n.dot(p[k] - p[0]) * n;
  } else if (what == 1) {  // one vertex on a's plane
    p[3] -= n.dot(p[3] - p[0]) * n;
  } else if (what == 2) {  // nearly parallel planes
    for (int k = 3; k < 6; ++k) p[k] -= 0.999999 * n.dot(p[k] - x) * n;
  } else if (what == 3) {  // a sliver
    p[2] = p[0] + (1 + 1e-14) * (p[1] - p[0]);
  } else if (what == 4) {  // b lifted until its lowest vertex nearly touches a's plane
    double lowest = 0;
    for (int k = 3; k < 6; ++k) lowest = std::min(lowest, n.dot(p[k] - p[0]));
    for (int k = 3; k < 6; ++k) p[k] -= lowest * (1 - 1e-13) * n;
  }
  return p;
}

void expect_same(const TriTriResult& e, const TriTriResult& a, long index) {
  ASSERT_EQ(e.intersects, a.intersects) << "pair " << index;
  ASSERT_EQ(e.coplanar, a.coplanar) << "pair " << index;
  ASSERT_EQ(e.p, a.p) << "pair " << index;
  ASSERT_EQ(e.q, a.q) << "pair " << index;
}

// Runs `kernel` (kLanes lanes) on random batches; every lane it answers must equal
// intersect_triangles bit for bit.
template <int kLanes, class Kernel>
void expect_kernel_matches(Kernel kernel) {
  std::mt19937 rng(2024);
  long answered = 0;
  long hits = 0;
  constexpr long kPairs = 400000;
  for (long batch = 0; batch < kPairs / kLanes; ++batch) {
    Pair pairs[kLanes];
    const Vec3* corners[kLanes][6];
    for (int k = 0; k < kLanes; ++k) {
      pairs[k] = random_pair(rng);
      for (int c = 0; c < 6; ++c) corners[k][c] = &pairs[k][c];
    }
    TriTriResult r[kLanes];
    const int done = kernel(corners, r);
    for (int k = 0; k < kLanes; ++k) {
      if (!(done >> k & 1)) continue;
      const Pair& p = pairs[k];
      const TriTriResult e = intersect_triangles(p[0], p[1], p[2], p[3], p[4], p[5]);
      expect_same(e, r[k], kLanes * batch + k);
      ++answered;
      hits += e.intersects ? 1 : 0;
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  // Most lanes are the common case, and many of those cross.
  EXPECT_GT(answered, kPairs / 2);
  EXPECT_GT(hits, answered / 5);
}

TEST(ExactBatch, FourLanesMatchIntersectTrianglesBitForBit) {
  if (!cpu_has_avx2()) GTEST_SKIP() << "no AVX2 here (or TROCAR_SIMD=off)";
  expect_kernel_matches<4>(
      [](const Vec3* const (&c)[4][6], TriTriResult (&r)[4]) { return narrow_detail::exact4_avx2(c, r); });
}

}  // namespace
}  // namespace trocar
