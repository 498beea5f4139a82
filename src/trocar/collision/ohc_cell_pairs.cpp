// OhcBroadPhase::emit_cell_pairs: the candidate pairs of one potential-colliding cell (step 7 of
// the cascade in docs/collision.md), with the box tests four partners at a time (AVX2, chosen at
// run time) or one by one.
#include <cstdint>

#include "trocar/collision/ohc_broad_phase.h"
#include "trocar/collision/ohc_kernels.h"
#include "trocar/core/cpu_features.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace trocar {

namespace {

/// A walked box (a_lo, a_hi) that misses the overlap (b_lo, b_hi) of the two grown cluster boxes
/// misses every box of the other cluster, since a box lies in its cluster's grown box.
inline bool misses_overlap(const Real (&a_lo)[3], const Real (&a_hi)[3], const Real (&b_lo)[3], const Real (&b_hi)[3]) {
  return a_lo[0] > b_hi[0] || b_lo[0] > a_hi[0] || a_lo[1] > b_hi[1] || b_lo[1] > a_hi[1] || a_lo[2] > b_hi[2] ||
         b_lo[2] > a_hi[2];
}

// Writes to `hits` the j in [begin, end) whose box (lo/hi: the cell's boxes, one array per axis
// and side) is not separated from box (a_lo, a_hi) on any axis; returns how many. Exact: the
// same comparisons as a scalar test (a NaN separates nothing, as there).
std::uint32_t box_hits_scalar(const Real* const (&lo)[3], const Real* const (&hi)[3], std::uint32_t begin,
                              std::uint32_t end, const Real (&a_lo)[3], const Real (&a_hi)[3], std::uint32_t* hits) {
  std::uint32_t count = 0;
  for (std::uint32_t j = begin; j < end; ++j) {
    if (a_lo[0] > hi[0][j] || lo[0][j] > a_hi[0] || a_lo[1] > hi[1][j] || lo[1][j] > a_hi[1] || a_lo[2] > hi[2][j] ||
        lo[2][j] > a_hi[2])
      continue;
    hits[count++] = j;
  }
  return count;
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same, four partners at a time (AVX2; chosen at run time). The arrays must be readable up to
// end + 3.
__attribute__((target("avx2"))) std::uint32_t box_hits_avx2(const Real* const (&lo)[3], const Real* const (&hi)[3],
                                                            std::uint32_t begin, std::uint32_t end,
                                                            const Real (&a_lo)[3], const Real (&a_hi)[3],
                                                            std::uint32_t* hits) {
  __m256d alo[3];
  __m256d ahi[3];
  for (int k = 0; k < 3; ++k) {
    alo[k] = _mm256_set1_pd(a_lo[k]);
    ahi[k] = _mm256_set1_pd(a_hi[k]);
  }
  std::uint32_t count = 0;
  for (std::uint32_t j = begin; j < end; j += 4) {
    __m256d apart = _mm256_setzero_pd();
    for (int k = 0; k < 3; ++k) {
      apart = _mm256_or_pd(apart, _mm256_cmp_pd(alo[k], _mm256_loadu_pd(hi[k] + j), _CMP_GT_OQ));
      apart = _mm256_or_pd(apart, _mm256_cmp_pd(_mm256_loadu_pd(lo[k] + j), ahi[k], _CMP_GT_OQ));
    }
    unsigned bits = ~static_cast<unsigned>(_mm256_movemask_pd(apart)) & 15u;
    if (end - j < 4) bits &= (1u << (end - j)) - 1u;
    // Branch-free compaction (the hits are few and random: a loop over the set bits mispredicts):
    // every lane is written, the count advances only past the hits. hits has room for 3 more.
    for (std::uint32_t t = 0; t < 4; ++t) {
      hits[count] = j + t;
      count += (bits >> t) & 1u;
    }
  }
  return count;
}
// The same, eight partners at a time (AVX-512; chosen at run time): one mask per block narrowed
// compare by compare (_CMP_NGT_UQ keeps a NaN, as the scalar test does), and the hits' indices
// compressed into place. `hits` must have room for 8 past the last hit; nothing past `end` is
// read (the last block's loads are masked).
__attribute__((target("avx512f,avx512vl,avx512dq"))) std::uint32_t box_hits_avx512(
    const Real* const (&lo)[3], const Real* const (&hi)[3], std::uint32_t begin, std::uint32_t end,
    const Real (&a_lo)[3], const Real (&a_hi)[3], std::uint32_t* hits) {
  __m512d alo[3];
  __m512d ahi[3];
  for (int k = 0; k < 3; ++k) {
    alo[k] = _mm512_set1_pd(a_lo[k]);
    ahi[k] = _mm512_set1_pd(a_hi[k]);
  }
  __m256i index = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(begin)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  std::uint32_t count = 0;
  for (std::uint32_t j = begin; j < end; j += 8) {
    const __mmask8 block = end - j >= 8 ? __mmask8{0xff} : static_cast<__mmask8>((1u << (end - j)) - 1u);
    __mmask8 m = block;
    for (int k = 0; k < 3; ++k) {
      m = _mm512_mask_cmp_pd_mask(m, alo[k], _mm512_maskz_loadu_pd(block, hi[k] + j), _CMP_NGT_UQ);
      m = _mm512_mask_cmp_pd_mask(m, _mm512_maskz_loadu_pd(block, lo[k] + j), ahi[k], _CMP_NGT_UQ);
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(hits + count), _mm256_maskz_compress_epi32(m, index));
    count += static_cast<std::uint32_t>(__builtin_popcount(m));
    index = _mm256_add_epi32(index, _mm256_set1_epi32(8));
  }
  return count;
}

// One cluster pair's candidates with AVX-512: each walked box that touches the overlap `both`
// of the two grown cluster boxes is tested against the other cluster's boxes eight at a time,
// and the hits' candidate pairs are built in registers (ids: object in the low, triangle in the
// high half; the walked one first when `outer_first`) and written at `out`, which needs room for
// 8 past the last. Returns how many were written. The same pairs, in the same order, as the
// scalar loop of emit_cluster_pairs.
__attribute__((target("avx512f,avx512vl,avx512dq"))) std::uint32_t cluster_pair_avx512(
    const Real* const (&lo)[3], const Real* const (&hi)[3], const Real* const (&dop_lo)[ohc_detail::kDopAxes],
    const Real* const (&dop_hi)[ohc_detail::kDopAxes], const std::uint64_t* ids, std::uint32_t outer_begin,
    std::uint32_t outer_end, std::uint32_t inner_begin, std::uint32_t inner_end, const Real (&b_lo)[3],
    const Real (&b_hi)[3], bool outer_first, CandidatePair* out) {
  static_assert(sizeof(CandidatePair) == 16, "four 32-bit ids");
  // Candidate k of a block of hits = 32-bit lanes 4k…4k+3 of (object_a, object_b, triangle_a,
  // triangle_b), taken from the hits' ids (lanes 0–15: object, triangle of hit 0, 1, …) and the
  // walked one's (lanes 16, 17).
  const __m512i walked_first_lo = _mm512_setr_epi32(16, 0, 17, 1, 16, 2, 17, 3, 16, 4, 17, 5, 16, 6, 17, 7);
  const __m512i walked_first_hi = _mm512_setr_epi32(16, 8, 17, 9, 16, 10, 17, 11, 16, 12, 17, 13, 16, 14, 17, 15);
  const __m512i walked_second_lo = _mm512_setr_epi32(0, 16, 1, 17, 2, 16, 3, 17, 4, 16, 5, 17, 6, 16, 7, 17);
  const __m512i walked_second_hi = _mm512_setr_epi32(8, 16, 9, 17, 10, 16, 11, 17, 12, 16, 13, 17, 14, 16, 15, 17);
  const __m512i shape_lo = outer_first ? walked_first_lo : walked_second_lo;
  const __m512i shape_hi = outer_first ? walked_first_hi : walked_second_hi;
  std::uint32_t written = 0;
  for (std::uint32_t a = outer_begin; a < outer_end; ++a) {
    const Real a_lo[3] = {lo[0][a], lo[1][a], lo[2][a]};
    const Real a_hi[3] = {hi[0][a], hi[1][a], hi[2][a]};
    if (misses_overlap(a_lo, a_hi, b_lo, b_hi)) continue;
    const __m512d alo[3] = {_mm512_set1_pd(a_lo[0]), _mm512_set1_pd(a_lo[1]), _mm512_set1_pd(a_lo[2])};
    const __m512d ahi[3] = {_mm512_set1_pd(a_hi[0]), _mm512_set1_pd(a_hi[1]), _mm512_set1_pd(a_hi[2])};
    const __m512i walked = _mm512_set1_epi64(static_cast<long long>(ids[a]));
    for (std::uint32_t j = inner_begin; j < inner_end; j += 8) {
      const __mmask8 block = inner_end - j >= 8 ? __mmask8{0xff} : static_cast<__mmask8>((1u << (inner_end - j)) - 1u);
      __mmask8 m = block;
      for (int k = 0; k < 3; ++k) {  // _CMP_NGT_UQ keeps a NaN, as the scalar test does
        m = _mm512_mask_cmp_pd_mask(m, alo[k], _mm512_maskz_loadu_pd(block, hi[k] + j), _CMP_NGT_UQ);
        m = _mm512_mask_cmp_pd_mask(m, _mm512_maskz_loadu_pd(block, lo[k] + j), ahi[k], _CMP_NGT_UQ);
      }
      if (m == 0) continue;
      // The box hits' extents along the six more directions (ohc_kernels.h).
      for (int k = 0; k < ohc_detail::kDopAxes; ++k) {
        const __m512d their_lo = _mm512_maskz_loadu_pd(m, dop_lo[k] + j);
        const __m512d their_hi = _mm512_maskz_loadu_pd(m, dop_hi[k] + j);
        m = _mm512_mask_cmp_pd_mask(m, _mm512_set1_pd(dop_lo[k][a]), their_hi, _CMP_NGT_UQ);
        m = _mm512_mask_cmp_pd_mask(m, their_lo, _mm512_set1_pd(dop_hi[k][a]), _CMP_NGT_UQ);
      }
      if (m == 0) continue;
      const __m512i hit_ids = _mm512_maskz_compress_epi64(m, _mm512_maskz_loadu_epi64(block, ids + j));
      _mm512_storeu_si512(out + written, _mm512_permutex2var_epi32(hit_ids, shape_lo, walked));
      _mm512_storeu_si512(out + written + 4, _mm512_permutex2var_epi32(hit_ids, shape_hi, walked));
      written += static_cast<std::uint32_t>(__builtin_popcount(m));
    }
  }
  return written;
}
#endif

// The box tests of one walked box against the cell's or cluster's range, by the widest kernel
// the CPU has (and the settings allow).
enum class BoxKernel { kScalar, kAvx2, kAvx512 };

BoxKernel box_kernel(bool simd) {
  if (!simd) return BoxKernel::kScalar;
  if (cpu_has_avx512()) return BoxKernel::kAvx512;
  return cpu_has_avx2() ? BoxKernel::kAvx2 : BoxKernel::kScalar;
}

std::uint32_t box_hits(BoxKernel kernel, const Real* const (&lo)[3], const Real* const (&hi)[3], std::uint32_t begin,
                       std::uint32_t end, const Real (&a_lo)[3], const Real (&a_hi)[3], std::uint32_t* hits) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (kernel == BoxKernel::kAvx512) return box_hits_avx512(lo, hi, begin, end, a_lo, a_hi, hits);
  if (kernel == BoxKernel::kAvx2) return box_hits_avx2(lo, hi, begin, end, a_lo, a_hi, hits);
#else
  (void)kernel;
#endif
  return box_hits_scalar(lo, hi, begin, end, a_lo, a_hi, hits);
}

}  // namespace

void OhcBroadPhase::emit_cell_pairs(std::span<const Entry> cell, std::span<const CollisionObject> objects,
                                    std::vector<CandidatePair>& out) {
  const auto n = static_cast<std::uint32_t>(objects.size());
  const auto size = static_cast<std::uint32_t>(cell.size());
  const std::int32_t cx = cell[0].x;
  const std::int32_t cy = cell[0].y;
  const std::int32_t cz = cell[0].z;
  // Dedup rule: emit a pair only from the cell holding the minimum corner of the boxes' overlap,
  // i.e. per axis the larger of the two first cells. Both first cells are ≤ this cell's, so the
  // rule holds iff on every axis at least one of the two starts here: with bit k set when a
  // primitive's first cell on axis k is this cell's, (starts_a | starts_b) == 7. Computed once
  // per entry. The boxes are copied into one array per axis and side, so that the box test (the
  // first one: it rejects ~85 % of the pairs here, the dedup rule ~40 %) takes four partners
  // at a time.
  std::uint8_t* starts = cell_starts_.data();
  Real* const lo[3] = {cell_boxes_.data(), cell_boxes_.data() + cell_stride_, cell_boxes_.data() + 2 * cell_stride_};
  Real* const hi[3] = {lo[2] + cell_stride_, lo[2] + 2 * cell_stride_, lo[2] + 3 * cell_stride_};
  // The cell is sorted by primitive and so by object: `groups` lists where each object's run
  // begins (and the end).
  std::uint32_t* groups = cell_groups_.data();
  std::uint32_t group_count = 0;
  std::uint32_t last_object = ~0u;
  for (std::uint32_t i = 0; i < size; ++i) {
    const Primitive& a = primitives_[cell[i].primitive];
    starts[i] = static_cast<std::uint8_t>((a.lo[0] == cx ? 1 : 0) | (a.lo[1] == cy ? 2 : 0) | (a.lo[2] == cz ? 4 : 0));
    for (int k = 0; k < 3; ++k) {
      lo[k][i] = a.min[k];
      hi[k][i] = a.max[k];
    }
    if (a.object != last_object) groups[group_count++] = i;
    last_object = a.object;
  }
  groups[group_count] = size;
  const Real* const clo[3] = {lo[0], lo[1], lo[2]};
  const Real* const chi[3] = {hi[0], hi[1], hi[2]};
  const BoxKernel kernel = box_kernel(settings_.simd);
  std::uint32_t* hits = cell_hits_.data();
  for (std::uint32_t g = 0; g + 1 < group_count; ++g) {
    const std::uint32_t object_g = primitives_[cell[groups[g]].primitive].object;
    for (std::uint32_t h = g + 1; h < group_count; ++h) {
      const std::uint32_t object_h = primitives_[cell[groups[h]].primitive].object;
      if (!tested_[static_cast<std::size_t>(object_g) * n + object_h]) continue;
      const bool g_first = object_first(objects[object_g].role, object_g, objects[object_h].role, object_h);
      const bool g_outside = groups[g + 1] - groups[g] <= groups[h + 1] - groups[h];
      const std::uint32_t outer = g_outside ? g : h;
      const std::uint32_t inner = g_outside ? h : g;
      for (std::uint32_t i = groups[outer]; i < groups[outer + 1]; ++i) {
        const Primitive& a = primitives_[cell[i].primitive];
        const Real a_lo[3] = {a.min[0], a.min[1], a.min[2]};
        const Real a_hi[3] = {a.max[0], a.max[1], a.max[2]};
        const std::uint32_t count = box_hits(kernel, clo, chi, groups[inner], groups[inner + 1], a_lo, a_hi, hits);
        const unsigned starts_a = starts[i];
        for (std::uint32_t k = 0; k < count; ++k) {
          const std::uint32_t j = hits[k];
          if ((starts_a | starts[j]) != 7u) continue;
          const Primitive& b = primitives_[cell[j].primitive];
          const Primitive& first = g_first == g_outside ? a : b;
          const Primitive& second = g_first == g_outside ? b : a;
          out.push_back({first.object, second.object, first.triangle, second.triangle});
        }
      }
    }
  }
}

}  // namespace trocar

namespace trocar {

void OhcBroadPhase::emit_cluster_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out,
                                       std::uint32_t opened) {
  // The opened triangles' clipped boxes (one array per axis and side; a cluster's triangles are
  // consecutive, so each cluster is a contiguous range of them).
  if (cell_hits_.size() < opened + 8) cell_hits_.resize(opened + 8);
  const Real* const lo[3] = {opened_boxes_.data(), opened_boxes_.data() + opened_stride_,
                             opened_boxes_.data() + 2 * opened_stride_};
  const Real* const hi[3] = {lo[2] + opened_stride_, lo[2] + 2 * opened_stride_, lo[2] + 3 * opened_stride_};
  const Real* dop_lo[ohc_detail::kDopAxes];
  const Real* dop_hi[ohc_detail::kDopAxes];
  for (int k = 0; k < ohc_detail::kDopAxes; ++k) {
    dop_lo[k] = opened_boxes_.data() + static_cast<std::size_t>(6 + k) * opened_stride_;
    dop_hi[k] = opened_boxes_.data() + static_cast<std::size_t>(6 + ohc_detail::kDopAxes + k) * opened_stride_;
  }
  const BoxKernel kernel = box_kernel(settings_.simd);
  std::uint32_t* hits = cell_hits_.data();
#if defined(__x86_64__) && defined(__GNUC__)
  // AVX-512: the candidates are built in registers into a scratch buffer with room for every
  // pair that could pass (Σ |P|·|Q| over the cluster pairs, bounded when this path was chosen).
  if (kernel == BoxKernel::kAvx512) {
    std::size_t bound = 8;
    for (const ClusterPair& cp : cluster_pair_list_) {
      bound += std::size_t{clusters_[cp.i].prim_count[cp.cluster_i]} * clusters_[cp.j].prim_count[cp.cluster_j];
    }
    if (pair_scratch_.size() < bound) pair_scratch_.resize(bound);
  }
#endif
  std::size_t written = 0;
  for (const ClusterPair& cp : cluster_pair_list_) {
    const std::uint32_t first_i = clusters_[cp.i].prim_first[cp.cluster_i];
    const std::uint32_t count_i = clusters_[cp.i].prim_count[cp.cluster_i];
    const std::uint32_t first_j = clusters_[cp.j].prim_first[cp.cluster_j];
    const std::uint32_t count_j = clusters_[cp.j].prim_count[cp.cluster_j];
    if (count_i == 0 || count_j == 0) continue;
    const bool i_first = object_first(objects[cp.i].role, cp.i, objects[cp.j].role, cp.j);
    // The smaller cluster walked, the larger one box-tested four at a time.
    const bool i_outside = count_i <= count_j;
    const std::uint32_t outer_begin = i_outside ? first_i : first_j;
    const std::uint32_t outer_end = outer_begin + (i_outside ? count_i : count_j);
    const std::uint32_t inner_begin = i_outside ? first_j : first_i;
    const std::uint32_t inner_end = inner_begin + (i_outside ? count_j : count_i);
    const bool outer_first = i_first == i_outside;
    const Real b_lo[3] = {cp.both.min.x(), cp.both.min.y(), cp.both.min.z()};
    const Real b_hi[3] = {cp.both.max.x(), cp.both.max.y(), cp.both.max.z()};
#if defined(__x86_64__) && defined(__GNUC__)
    if (kernel == BoxKernel::kAvx512) {
      written += cluster_pair_avx512(lo, hi, dop_lo, dop_hi, reinterpret_cast<const std::uint64_t*>(opened_ids_.data()),
                                     outer_begin,
                                     outer_end, inner_begin, inner_end, b_lo, b_hi, outer_first,
                                     pair_scratch_.data() + written);
      continue;
    }
#endif
    for (std::uint32_t a = outer_begin; a < outer_end; ++a) {
      const Real a_lo[3] = {lo[0][a], lo[1][a], lo[2][a]};
      const Real a_hi[3] = {hi[0][a], hi[1][a], hi[2][a]};
      if (misses_overlap(a_lo, a_hi, b_lo, b_hi)) continue;
      const std::uint32_t n_hits = box_hits(kernel, lo, hi, inner_begin, inner_end, a_lo, a_hi, hits);
      const OpenedId pa = opened_ids_[a];
      for (std::uint32_t k = 0; k < n_hits; ++k) {
        const std::uint32_t b = hits[k];
        bool apart = false;  // along one of the six more directions (as the AVX-512 kernel)
        for (int d = 0; d < ohc_detail::kDopAxes; ++d) {
          apart |= dop_lo[d][a] > dop_hi[d][b] || dop_lo[d][b] > dop_hi[d][a];
        }
        if (apart) continue;
        const OpenedId pb = opened_ids_[b];
        const OpenedId first = outer_first ? pa : pb;
        const OpenedId second = outer_first ? pb : pa;
        out.push_back({first.object, second.object, first.triangle, second.triangle});
      }
    }
  }
  out.insert(out.end(), pair_scratch_.begin(), pair_scratch_.begin() + static_cast<std::ptrdiff_t>(written));
}

}  // namespace trocar
