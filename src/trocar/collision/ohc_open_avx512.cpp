// The OHC's opening of a cluster (step 3 of the cascade in docs/collision.md), eight triangles at
// a time with AVX-512: corners by masked loads and transposes, the raw box test against the
// grown clip region, the inflated box (triangle_box: kBoxMargin of its largest side) clipped to
// the region, and the survivors compressed into the opened arrays. Min, max, the margin's one
// product and its sums are the scalar loop's operations, so the boxes are the same.
#include "trocar/collision/ohc_kernels.h"

#include <cstdlib>

#include "trocar/collision/broad_phase.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TROCAR_OHC_AVX512 1
// GCC 12's AVX-512 headers pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins of _mm512_insertf64x4 and friends, which -Wuninitialized reports once inlined here.
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)  // a GCC-only warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#endif

namespace trocar::ohc_detail {

#if defined(TROCAR_OHC_AVX512)
namespace {

#define TROCAR_AVX512 __attribute__((target("avx512f,avx512vl,avx512dq,avx2"), always_inline)) inline

struct W3 {
  __m512d x, y, z;
};

// Two points in one register (three coordinates each, nothing past them read).
TROCAR_AVX512 __m512d two(const double* lo, const double* hi) {
  return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, lo)), _mm256_maskz_loadu_pd(0x7, hi), 1);
}
// Eight points as x, y, z vectors: two 4×3 transposes in 512-bit registers.
TROCAR_AVX512 W3 load8(const double* const (&p)[8]) {
  const __m512d a = two(p[0], p[2]);
  const __m512d b = two(p[1], p[3]);
  const __m512d c = two(p[4], p[6]);
  const __m512d d = two(p[5], p[7]);
  const __m512d xz_ab = _mm512_unpacklo_pd(a, b);
  const __m512d y_ab = _mm512_unpackhi_pd(a, b);
  const __m512d xz_cd = _mm512_unpacklo_pd(c, d);
  const __m512d y_cd = _mm512_unpackhi_pd(c, d);
  constexpr int kEven = _MM_SHUFFLE(2, 0, 2, 0);
  constexpr int kOdd = _MM_SHUFFLE(3, 1, 3, 1);
  return {_mm512_shuffle_f64x2(xz_ab, xz_cd, kEven), _mm512_shuffle_f64x2(y_ab, y_cd, kEven),
          _mm512_shuffle_f64x2(xz_ab, xz_cd, kOdd)};
}

}  // namespace

__attribute__((target("avx512f,avx512vl,avx512dq,avx2"))) std::uint32_t open_cluster_avx512(
    const Vec3* positions, const Triangle* ordered, const std::uint32_t* order, std::uint32_t count,
    std::uint32_t object, const Real (&clip_lo)[3], const Real (&clip_hi)[3], const Real (&grown_lo)[3],
    const Real (&grown_hi)[3], const OpenedArrays& out, std::uint32_t at) {
  const __m512d c_lo[3] = {_mm512_set1_pd(clip_lo[0]), _mm512_set1_pd(clip_lo[1]), _mm512_set1_pd(clip_lo[2])};
  const __m512d c_hi[3] = {_mm512_set1_pd(clip_hi[0]), _mm512_set1_pd(clip_hi[1]), _mm512_set1_pd(clip_hi[2])};
  const __m512d g_lo[3] = {_mm512_set1_pd(grown_lo[0]), _mm512_set1_pd(grown_lo[1]), _mm512_set1_pd(grown_lo[2])};
  const __m512d g_hi[3] = {_mm512_set1_pd(grown_hi[0]), _mm512_set1_pd(grown_hi[1]), _mm512_set1_pd(grown_hi[2])};
  const __m512i object_id = _mm512_set1_epi64(static_cast<long long>(object));
  for (std::uint32_t first = 0; first < count; first += 8) {
    const std::uint32_t lanes = count - first < 8 ? count - first : 8;
    const auto valid = static_cast<__mmask8>((1u << lanes) - 1u);
    // Corner k of the eight triangles; a last, short batch is padded with its first triangle
    // (a copy, so that full batches index without a select per lane).
    const Triangle* tri = ordered + first;
    Triangle padded[8];
    if (lanes < 8) {
      for (std::uint32_t t = 0; t < 8; ++t) padded[t] = tri[t < lanes ? t : 0];
      tri = padded;
    }
    W3 corner[3];
    for (int k = 0; k < 3; ++k) {
      const double* p[8];
      for (std::uint32_t t = 0; t < 8; ++t) p[t] = positions[tri[t][static_cast<std::size_t>(k)]].data();
      corner[k] = load8(p);
    }
    // Raw box: min(min(a, b), c) with std::min's operand order (min_pd returns its second operand
    // on a NaN, as std::min(u, v) = v < u ? v : u returns u).
    const __m512d lo[3] = {_mm512_min_pd(corner[2].x, _mm512_min_pd(corner[1].x, corner[0].x)),
                           _mm512_min_pd(corner[2].y, _mm512_min_pd(corner[1].y, corner[0].y)),
                           _mm512_min_pd(corner[2].z, _mm512_min_pd(corner[1].z, corner[0].z))};
    const __m512d hi[3] = {_mm512_max_pd(corner[2].x, _mm512_max_pd(corner[1].x, corner[0].x)),
                           _mm512_max_pd(corner[2].y, _mm512_max_pd(corner[1].y, corner[0].y)),
                           _mm512_max_pd(corner[2].z, _mm512_max_pd(corner[1].z, corner[0].z))};
    __mmask8 keep = valid;
    for (int k = 0; k < 3; ++k) {
      keep &= static_cast<__mmask8>(~(_mm512_cmp_pd_mask(hi[k], g_lo[k], _CMP_LT_OQ) |
                                      _mm512_cmp_pd_mask(lo[k], g_hi[k], _CMP_GT_OQ)));
    }
    if (keep == 0) continue;
    // Inflated by kBoxMargin of the largest side, then clipped; empty ones dropped.
    const __m512d side = _mm512_max_pd(_mm512_max_pd(_mm512_sub_pd(hi[0], lo[0]), _mm512_sub_pd(hi[1], lo[1])),
                                       _mm512_sub_pd(hi[2], lo[2]));
    // (This file is compiled with -ffp-contract=off: no product is fused into the sums below,
    // which would round differently from the scalar code.)
    const __m512d margin = _mm512_mul_pd(_mm512_set1_pd(kBoxMargin), side);
    __m512d box_lo[3];
    __m512d box_hi[3];
    for (int k = 0; k < 3; ++k) {
      box_lo[k] = _mm512_max_pd(_mm512_sub_pd(lo[k], margin), c_lo[k]);
      box_hi[k] = _mm512_min_pd(_mm512_add_pd(hi[k], margin), c_hi[k]);
      keep &= static_cast<__mmask8>(~_mm512_cmp_pd_mask(box_lo[k], box_hi[k], _CMP_GT_OQ));
    }
    if (keep == 0) continue;
    for (int k = 0; k < 3; ++k) {
      _mm512_storeu_pd(out.lo[k] + at, _mm512_maskz_compress_pd(keep, box_lo[k]));
      _mm512_storeu_pd(out.hi[k] + at, _mm512_maskz_compress_pd(keep, box_hi[k]));
    }
    // The extents along x ± y, x ± z, y ± z, widened as dop_extents() does.
    const __m512d scale = _mm512_max_pd(
        _mm512_max_pd(_mm512_max_pd(_mm512_abs_pd(lo[0]), _mm512_abs_pd(hi[0])),
                      _mm512_max_pd(_mm512_abs_pd(lo[1]), _mm512_abs_pd(hi[1]))),
        _mm512_max_pd(_mm512_abs_pd(lo[2]), _mm512_abs_pd(hi[2])));
    const __m512d w =
        _mm512_add_pd(_mm512_mul_pd(_mm512_set1_pd(2.0), margin), _mm512_mul_pd(_mm512_set1_pd(4e-15), scale));
    for (int k = 0; k < kDopAxes; ++k) {
      __m512d along[3];
      for (int v = 0; v < 3; ++v) {
        const __m512d first_axis = k < 4 ? corner[v].x : corner[v].y;
        const __m512d second_axis = k == 0 || k == 1 ? corner[v].y : corner[v].z;
        along[v] = k % 2 == 0 ? _mm512_add_pd(first_axis, second_axis) : _mm512_sub_pd(first_axis, second_axis);
      }
      const __m512d d_lo = _mm512_sub_pd(_mm512_min_pd(along[2], _mm512_min_pd(along[1], along[0])), w);
      const __m512d d_hi = _mm512_add_pd(_mm512_max_pd(along[2], _mm512_max_pd(along[1], along[0])), w);
      _mm512_storeu_pd(out.dop_lo[k] + at, _mm512_maskz_compress_pd(keep, d_lo));
      _mm512_storeu_pd(out.dop_hi[k] + at, _mm512_maskz_compress_pd(keep, d_hi));
    }
    const __m512i triangles = _mm512_cvtepu32_epi64(_mm256_maskz_loadu_epi32(valid, order + first));
    const __m512i ids = _mm512_or_si512(object_id, _mm512_slli_epi64(triangles, 32));
    _mm512_storeu_si512(out.ids + at, _mm512_maskz_compress_epi64(keep, ids));
    at += static_cast<std::uint32_t>(__builtin_popcount(keep));
  }
  return at;
}

#else

std::uint32_t open_cluster_avx512(const Vec3*, const Triangle*, const std::uint32_t*, std::uint32_t, std::uint32_t,
                                  const Real (&)[3], const Real (&)[3], const Real (&)[3], const Real (&)[3],
                                  const OpenedArrays&, std::uint32_t) {
  std::abort();  // never called: cpu_has_avx512() is false
}

#endif

}  // namespace trocar::ohc_detail
