#pragma once
/// Internal to the OHC (ohc_broad_phase.cpp): its AVX-512 kernels, chosen at run time.
#include <cstdint>

#include "trocar/core/types.h"

namespace trocar::ohc_detail {

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
