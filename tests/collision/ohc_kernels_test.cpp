// The OHC's AVX-512 opening of a cluster (ohc_detail::open_cluster_avx512) against the scalar
// loop's definition: the triangles whose raw box touches the grown region and whose inflated box
// (triangle_box) clipped to the region is not empty, with those boxes and their extents along
// the six more directions (ohc_detail::dop_extents) bit for bit.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/ohc_kernels.h"
#include "trocar/core/cpu_features.h"

namespace trocar {
namespace {

TEST(OhcKernels, OpenClusterMatchesScalarBitForBit) {
  if (!cpu_has_avx512()) GTEST_SKIP() << "no AVX-512 here (or TROCAR_SIMD=off)";
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 199);
  std::vector<Vec3> positions(200);
  std::vector<Real> arrays(18 * 48);
  std::vector<std::uint64_t> ids(48);
  std::size_t kept = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, 4 * u(rng));
    for (Vec3& p : positions) p = scale * Vec3(u(rng), u(rng), u(rng)) + Vec3(1e3 * u(rng), 0, 0);
    const auto count = static_cast<std::uint32_t>(1 + trial % 32);
    std::vector<Triangle> ordered(count);
    std::vector<std::uint32_t> order(count);
    for (std::uint32_t t = 0; t < count; ++t) {
      ordered[t] = {static_cast<std::uint32_t>(pick(rng)), static_cast<std::uint32_t>(pick(rng)),
                    static_cast<std::uint32_t>(pick(rng))};
      order[t] = 1000 + t;
    }
    Aabb clip;
    clip.min = positions[0].cwiseMin(positions[1]);
    clip.max = positions[0].cwiseMax(positions[1]);
    if (trial % 3 == 0) clip.max.y() = clip.min.y();  // a flat region
    const Aabb grown = clip.inflated(1e-9 * scale);
    const Real c_lo[3] = {clip.min.x(), clip.min.y(), clip.min.z()};
    const Real c_hi[3] = {clip.max.x(), clip.max.y(), clip.max.z()};
    const Real g_lo[3] = {grown.min.x(), grown.min.y(), grown.min.z()};
    const Real g_hi[3] = {grown.max.x(), grown.max.y(), grown.max.z()};
    Real* base = arrays.data();
    ohc_detail::OpenedArrays out = {
        {base, base + 48, base + 96}, {base + 144, base + 192, base + 240}, {}, {}, ids.data()};
    for (int d = 0; d < ohc_detail::kDopAxes; ++d) {
      out.dop_lo[d] = base + 48 * (6 + d);
      out.dop_hi[d] = base + 48 * (12 + d);
    }
    const std::uint32_t at = 3;  // written after three earlier entries
    const std::uint32_t end = ohc_detail::open_cluster_avx512(positions.data(), ordered.data(), order.data(), count,
                                                             7, c_lo, c_hi, g_lo, g_hi, out, at);
    std::uint32_t e = at;
    for (std::uint32_t t = 0; t < count; ++t) {
      const Vec3& a = positions[ordered[t][0]];
      const Vec3& b = positions[ordered[t][1]];
      const Vec3& c = positions[ordered[t][2]];
      const Aabb raw{a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
      if (!raw.overlaps(grown)) continue;
      const Aabb box = triangle_box(a, b, c).intersection(clip);
      if (box.is_empty()) continue;
      ASSERT_LT(e, end) << "trial " << trial;
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(out.lo[k][e], box.min[k]) << "trial " << trial << " triangle " << t;
        EXPECT_EQ(out.hi[k][e], box.max[k]) << "trial " << trial << " triangle " << t;
      }
      Real d_lo[ohc_detail::kDopAxes];
      Real d_hi[ohc_detail::kDopAxes];
      ohc_detail::dop_extents(a, b, c, d_lo, d_hi);
      for (int d = 0; d < ohc_detail::kDopAxes; ++d) {
        EXPECT_EQ(out.dop_lo[d][e], d_lo[d]) << "trial " << trial << " triangle " << t << " direction " << d;
        EXPECT_EQ(out.dop_hi[d][e], d_hi[d]) << "trial " << trial << " triangle " << t << " direction " << d;
      }
      EXPECT_EQ(ids[e], 7u | (std::uint64_t{1000 + t} << 32));
      ++e;
      ++kept;
    }
    ASSERT_EQ(e, end) << "trial " << trial;
  }
  EXPECT_GT(kept, 1000u);
}

}  // namespace
}  // namespace trocar
