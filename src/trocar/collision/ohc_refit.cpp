// The OHC's refit (step 1 of the cascade in docs/collision.md): boxes of vertex lists, the groups'
// every frame and the clusters' of the groups the cluster sweep needs. One 32-byte load brings a
// vertex's x, y, z (and the next vertex's x in the fourth lane, never used): one min and one max
// per vertex, two accumulators to break the latency chain (AVX2, chosen at run time; SSE2 with x,
// y in one register and z in another otherwise). min/max of doubles are exact, so both paths give
// the same boxes except possibly for the sign of a zero or which NaN.
#include <algorithm>
#include <limits>

#include "trocar/collision/ohc_kernels.h"
#include "trocar/core/cpu_features.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TROCAR_OHC_AVX2 1
#endif

namespace trocar::ohc_detail {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

#if defined(TROCAR_OHC_AVX2)
// min/max returning the accumulator when x is NaN (kSkipNaN: _mm256_min_pd returns its second
// operand on a NaN), or x (the NaN) otherwise.
template <bool kSkipNaN>
__attribute__((target("avx2"), always_inline)) inline __m256d min4(__m256d acc, __m256d x) {
  return kSkipNaN ? _mm256_min_pd(x, acc) : _mm256_min_pd(acc, x);
}
template <bool kSkipNaN>
__attribute__((target("avx2"), always_inline)) inline __m256d max4(__m256d acc, __m256d x) {
  return kSkipNaN ? _mm256_max_pd(x, acc) : _mm256_max_pd(acc, x);
}

template <bool kPrefetch, bool kSkipNaN>
__attribute__((target("avx2"))) void refit_avx2(const Real* p, const std::uint32_t* ids, const std::uint32_t* starts,
                                                std::size_t count, Aabb* boxes, Real (&olo)[3], Real (&ohi)[3]) {
  const __m256i mask = _mm256_setr_epi64x(-1, -1, -1, 0);
  __m256d obj_lo = _mm256_set1_pd(kInf);
  __m256d obj_hi = _mm256_set1_pd(-kInf);
  for (std::size_t k = 0; k < count; ++k) {
    __m256d lo0 = _mm256_set1_pd(kInf), lo1 = lo0, hi0 = _mm256_set1_pd(-kInf), hi1 = hi0;
    // Pointers rather than 32-bit indices: no zero-extension per step. Four vertices per step,
    // one prefetch per step (a prefetched line usually holds the next ids' vertices too).
    const std::uint32_t* it = ids + starts[k];
    const std::uint32_t* last = ids + starts[k + 1] - 1;
    for (; it + 3 < last; it += 4) {
      // Large meshes: the ids run on past this list (padded at the end), so the vertices ~40
      // clusters ahead are requested now; positions just rewritten come from memory, and the
      // lists' scattered rows defeat the hardware prefetcher. (Small meshes sit in cache.)
      if constexpr (kPrefetch) {
        _mm_prefetch(reinterpret_cast<const char*>(p + it[kRefitPrefetch]), _MM_HINT_T1);
        _mm_prefetch(reinterpret_cast<const char*>(p + it[kRefitPrefetch + 2]), _MM_HINT_T1);
      }
      const __m256d x0 = _mm256_loadu_pd(p + it[0]);
      const __m256d x1 = _mm256_loadu_pd(p + it[1]);
      const __m256d x2 = _mm256_loadu_pd(p + it[2]);
      const __m256d x3 = _mm256_loadu_pd(p + it[3]);
      lo0 = min4<kSkipNaN>(lo0, min4<kSkipNaN>(x0, x2));
      hi0 = max4<kSkipNaN>(hi0, max4<kSkipNaN>(x0, x2));
      lo1 = min4<kSkipNaN>(lo1, min4<kSkipNaN>(x1, x3));
      hi1 = max4<kSkipNaN>(hi1, max4<kSkipNaN>(x1, x3));
    }
    for (; it < last; ++it) {
      const __m256d x0 = _mm256_loadu_pd(p + *it);
      lo0 = min4<kSkipNaN>(lo0, x0);
      hi0 = max4<kSkipNaN>(hi0, x0);
    }
    const __m256d x_last = _mm256_maskload_pd(p + *last, mask);  // the fourth lane is not read
    lo1 = min4<kSkipNaN>(lo1, x_last);
    hi1 = max4<kSkipNaN>(hi1, x_last);
    const __m256d lo = min4<kSkipNaN>(lo0, lo1);
    const __m256d hi = max4<kSkipNaN>(hi0, hi1);
    alignas(32) Real l[4];
    alignas(32) Real h[4];
    _mm256_store_pd(l, lo);
    _mm256_store_pd(h, hi);
    boxes[k].min = Vec3(l[0], l[1], l[2]);
    boxes[k].max = Vec3(h[0], h[1], h[2]);
    obj_lo = _mm256_min_pd(lo, obj_lo);  // = std::min(obj_lo, lo): a NaN box is left out
    obj_hi = _mm256_max_pd(hi, obj_hi);
  }
  alignas(32) Real l[4];
  alignas(32) Real h[4];
  _mm256_store_pd(l, obj_lo);
  _mm256_store_pd(h, obj_hi);
  for (int a = 0; a < 3; ++a) {
    olo[a] = l[a];
    ohi[a] = h[a];
  }
}
#endif

#if defined(__SSE2__)
template <bool kSkipNaN>
inline __m128d min2(__m128d acc, __m128d x) {
  return kSkipNaN ? _mm_min_pd(x, acc) : _mm_min_pd(acc, x);
}
template <bool kSkipNaN>
inline __m128d max2(__m128d acc, __m128d x) {
  return kSkipNaN ? _mm_max_pd(x, acc) : _mm_max_pd(acc, x);
}
#endif

// The portable refit: x and y packed in one register, z alone (SSE2), two accumulators.
template <bool kSkipNaN>
void refit_sse2(const Real* p, const std::uint32_t* ids, const std::uint32_t* starts, std::size_t count, Aabb* boxes,
                Real (&olo)[3], Real (&ohi)[3]) {
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t begin = starts[k];
    const std::uint32_t end = starts[k + 1];
    Real lo[3];
    Real hi[3];
#if defined(__SSE2__)
    __m128d lo_xy0 = _mm_set1_pd(kInf), lo_xy1 = lo_xy0, hi_xy0 = _mm_set1_pd(-kInf), hi_xy1 = hi_xy0;
    __m128d lo_z0 = _mm_set1_pd(kInf), lo_z1 = lo_z0, hi_z0 = _mm_set1_pd(-kInf), hi_z1 = hi_z0;
    std::uint32_t i = begin;
    for (; i + 1 < end; i += 2) {
      const Real* x0 = p + ids[i];
      const Real* x1 = p + ids[i + 1];
      lo_xy0 = min2<kSkipNaN>(lo_xy0, _mm_loadu_pd(x0));
      hi_xy0 = max2<kSkipNaN>(hi_xy0, _mm_loadu_pd(x0));
      lo_xy1 = min2<kSkipNaN>(lo_xy1, _mm_loadu_pd(x1));
      hi_xy1 = max2<kSkipNaN>(hi_xy1, _mm_loadu_pd(x1));
      lo_z0 = min2<kSkipNaN>(lo_z0, _mm_load_sd(x0 + 2));  // the upper lane (0) is never used
      hi_z0 = max2<kSkipNaN>(hi_z0, _mm_load_sd(x0 + 2));
      lo_z1 = min2<kSkipNaN>(lo_z1, _mm_load_sd(x1 + 2));
      hi_z1 = max2<kSkipNaN>(hi_z1, _mm_load_sd(x1 + 2));
    }
    if (i < end) {
      const Real* x0 = p + ids[i];
      lo_xy0 = min2<kSkipNaN>(lo_xy0, _mm_loadu_pd(x0));
      hi_xy0 = max2<kSkipNaN>(hi_xy0, _mm_loadu_pd(x0));
      lo_z0 = min2<kSkipNaN>(lo_z0, _mm_load_sd(x0 + 2));
      hi_z0 = max2<kSkipNaN>(hi_z0, _mm_load_sd(x0 + 2));
    }
    _mm_storeu_pd(lo, min2<kSkipNaN>(lo_xy0, lo_xy1));
    _mm_storeu_pd(hi, max2<kSkipNaN>(hi_xy0, hi_xy1));
    _mm_store_sd(lo + 2, min2<kSkipNaN>(lo_z0, lo_z1));
    _mm_store_sd(hi + 2, max2<kSkipNaN>(hi_z0, hi_z1));
#else
    for (int a = 0; a < 3; ++a) {
      lo[a] = kInf;
      hi[a] = -kInf;
    }
    for (std::uint32_t i = begin; i < end; ++i) {
      const Real* x = p + ids[i];
      for (int a = 0; a < 3; ++a) {
        // std::min(u, v) = v < u ? v : u keeps u when v is NaN.
        lo[a] = kSkipNaN ? std::min(lo[a], x[a]) : std::min(x[a], lo[a]);
        hi[a] = kSkipNaN ? std::max(hi[a], x[a]) : std::max(x[a], hi[a]);
      }
    }
#endif
    boxes[k].min = Vec3(lo[0], lo[1], lo[2]);
    boxes[k].max = Vec3(hi[0], hi[1], hi[2]);
    for (int a = 0; a < 3; ++a) {
      olo[a] = std::min(olo[a], lo[a]);  // a NaN box is left out
      ohi[a] = std::max(ohi[a], hi[a]);
    }
  }
}

}  // namespace

void refit_lists(const Real* positions, const std::uint32_t* ids, const std::uint32_t* starts, std::size_t count,
                 Aabb* boxes, Real (&lo)[3], Real (&hi)[3], bool skip_nan, bool simd, bool prefetch) {
  for (int a = 0; a < 3; ++a) {
    lo[a] = kInf;
    hi[a] = -kInf;
  }
#if defined(TROCAR_OHC_AVX2)
  if (simd && cpu_has_avx2()) {
    if (prefetch) {
      skip_nan ? refit_avx2<true, true>(positions, ids, starts, count, boxes, lo, hi)
               : refit_avx2<true, false>(positions, ids, starts, count, boxes, lo, hi);
    } else {
      skip_nan ? refit_avx2<false, true>(positions, ids, starts, count, boxes, lo, hi)
               : refit_avx2<false, false>(positions, ids, starts, count, boxes, lo, hi);
    }
    return;
  }
#endif
  (void)prefetch;  // the portable path does not prefetch
  skip_nan ? refit_sse2<true>(positions, ids, starts, count, boxes, lo, hi)
           : refit_sse2<false>(positions, ids, starts, count, boxes, lo, hi);
}

}  // namespace trocar::ohc_detail
