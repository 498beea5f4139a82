#pragma once
/// Internal to the OHC (ohc_broad_phase.cpp): its refit and its AVX-512 kernels.
#include <cstddef>
#include <cstdint>

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "trocar/collision/broad_phase.h"
#include "trocar/core/aabb.h"
#include "trocar/core/types.h"

namespace trocar::ohc_detail {

// How far ahead (in vertex list entries, ~40 clusters or 30 KB of positions) the refit
// prefetches positions (into L2). Measured on the 720K sheet (bench_collision, scene c): 48
// entries 1.8 ms per frame, 160 1.5 ms, 640 1.2 ms, 1280 1.1 ms, 2560 1.1 ms; memory latency
// here is long compared with the ~1.5 ns a vertex takes. Every vertex list is padded this far.
inline constexpr std::uint32_t kRefitPrefetch = 1280;
// Objects with more vertices than this (1.5 MB of positions, beyond a core's L2) are prefetched.
inline constexpr std::size_t kRefitPrefetchVertices = 65536;

/// Boxes of `count` vertex lists: list k is ids[starts[k]] … ids[starts[k + 1] − 1], ascending
/// offsets in doubles into `positions` (3 × vertex id), never empty; boxes[k] gets its box and
/// (lo, hi) the union of all. `skip_nan`: a NaN coordinate is left out of every box (the group
/// boxes, which must hold the other vertices whatever one of them holds); otherwise it makes its
/// list's box NaN (a cluster whose box then overlaps nothing) and is left out of the union. AVX2
/// where `simd` and the CPU has it, else SSE2; with `prefetch` the vertices kRefitPrefetch
/// entries ahead are requested. Only the last entry of a list can be the last vertex of the
/// positions, and nothing past them is read.
void refit_lists(const Real* positions, const std::uint32_t* ids, const std::uint32_t* starts, std::size_t count,
                 Aabb* boxes, Real (&lo)[3], Real (&hi)[3], bool skip_nan, bool simd, bool prefetch);

/// Besides its box, each opened triangle gets its extents along six more directions (x + y,
/// x − y, x + z, x − z, y + z, y − z: with the box, an 18-DOP), which the cluster-pair path tests
/// after the boxes: a tilted triangle's box is much larger than the triangle, and these reject
/// about half of the box hits (bench_collision scene a) before the narrow phase. Each extent is
/// widened by w = 2·(the box margin) + 4e-15·(the triangle's largest coordinate): the first
/// covers the narrow phase's tolerance as the box margin does (a direction has length √2 < 2),
/// the second the rounding of the sums and of the widening (each ≤ 2.2e-16·scale per end).
inline constexpr int kDopAxes = 6;

/// The six extents of triangle abc, widened (the definition both opening paths follow).
inline void dop_extents(const Vec3& a, const Vec3& b, const Vec3& c, Real (&lo)[kDopAxes], Real (&hi)[kDopAxes]) {
  Real side = 0;
  Real scale = 0;
  for (int k = 0; k < 3; ++k) {
    const Real l = std::min(std::min(a[k], b[k]), c[k]);
    const Real h = std::max(std::max(a[k], b[k]), c[k]);
    side = std::max(side, h - l);
    scale = std::max(scale, std::max(std::abs(l), std::abs(h)));
  }
  const Real w = 2.0 * (kBoxMargin * side) + 4e-15 * scale;
#if defined(__SSE2__)
  // Two directions per register: (u, u) + (v, −v) is (u + v, u − v) exactly. std::min(p, q) is
  // _mm_min_pd(q, p), so these are the scalar expressions below.
  const auto along = [](const Vec3& x, int first, int second) {
    return _mm_add_pd(_mm_set1_pd(x[first]), _mm_set_pd(-x[second], x[second]));
  };
  const int axes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int d = 0; d < 3; ++d) {
    const __m128d pa = along(a, axes[d][0], axes[d][1]);
    const __m128d pb = along(b, axes[d][0], axes[d][1]);
    const __m128d pc = along(c, axes[d][0], axes[d][1]);
    _mm_storeu_pd(lo + 2 * d, _mm_sub_pd(_mm_min_pd(pc, _mm_min_pd(pb, pa)), _mm_set1_pd(w)));
    _mm_storeu_pd(hi + 2 * d, _mm_add_pd(_mm_max_pd(pc, _mm_max_pd(pb, pa)), _mm_set1_pd(w)));
  }
#else
  const Real pa[kDopAxes] = {a.x() + a.y(), a.x() - a.y(), a.x() + a.z(), a.x() - a.z(), a.y() + a.z(), a.y() - a.z()};
  const Real pb[kDopAxes] = {b.x() + b.y(), b.x() - b.y(), b.x() + b.z(), b.x() - b.z(), b.y() + b.z(), b.y() - b.z()};
  const Real pc[kDopAxes] = {c.x() + c.y(), c.x() - c.y(), c.x() + c.z(), c.x() - c.z(), c.y() + c.z(), c.y() - c.z()};
  for (int k = 0; k < kDopAxes; ++k) {
    lo[k] = std::min(std::min(pa[k], pb[k]), pc[k]) - w;
    hi[k] = std::max(std::max(pa[k], pb[k]), pc[k]) + w;
  }
#endif
}

/// Where a cluster's opened triangles go: their clipped boxes (one array per axis and side), their
/// extents along the six more directions (dop_extents), and their ids (object in the low,
/// triangle in the high 32 bits: OhcBroadPhase::OpenedId).
struct OpenedArrays {
  Real* lo[3];
  Real* hi[3];
  Real* dop_lo[kDopAxes];
  Real* dop_hi[kDopAxes];
  std::uint64_t* ids;
};

/// Opens `count` (≤ 32) consecutive triangles of a cluster, eight at a time (AVX-512): those whose
/// raw box touches [grown_lo, grown_hi] and whose inflated box (triangle_box) clipped to
/// [clip_lo, clip_hi] is not empty are written at out[at…], in order; returns the new end. The
/// same triangles and boxes as open_cluster_portable (ohc_broad_phase.cpp). The arrays need room
/// for 8 entries past the last one written. Requires cpu_has_avx512().
std::uint32_t open_cluster_avx512(const Vec3* positions, const Triangle* ordered, const std::uint32_t* order,
                                  std::uint32_t count, std::uint32_t object, const Real (&clip_lo)[3],
                                  const Real (&clip_hi)[3], const Real (&grown_lo)[3], const Real (&grown_hi)[3],
                                  const OpenedArrays& out, std::uint32_t at);

}  // namespace trocar::ohc_detail
