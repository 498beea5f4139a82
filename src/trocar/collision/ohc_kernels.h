#pragma once
/// Internal to the OHC (ohc_broad_phase.cpp): its refit and its AVX-512 kernels.
#include <cstddef>
#include <cstdint>

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

/// Where a cluster's opened triangles go: their clipped boxes (one array per axis and side) and
/// their ids (object in the low, triangle in the high 32 bits: OhcBroadPhase::OpenedId).
struct OpenedArrays {
  Real* lo[3];
  Real* hi[3];
  std::uint64_t* ids;
};

/// Opens `count` (≤ 32) consecutive triangles of a cluster, eight at a time (AVX-512): those whose
/// raw box touches [grown_lo, grown_hi] and whose inflated box (triangle_box) clipped to
/// [clip_lo, clip_hi] is not empty are written at out[at…], in order; returns the new end. The
/// same triangles and boxes as the scalar loop of OhcBroadPhase::find_pairs. The arrays need room
/// for 8 entries past the last one written. Requires cpu_has_avx512().
std::uint32_t open_cluster_avx512(const Vec3* positions, const Triangle* ordered, const std::uint32_t* order,
                                  std::uint32_t count, std::uint32_t object, const Real (&clip_lo)[3],
                                  const Real (&clip_hi)[3], const Real (&grown_lo)[3], const Real (&grown_hi)[3],
                                  const OpenedArrays& out, std::uint32_t at);

}  // namespace trocar::ohc_detail
