// exact8_avx512: the narrow phase's exact test on eight pairs at once (narrow_phase_exact.h)
// with AVX-512, compiled with -ffp-contract=off (CMakeLists.txt): AVX-512 brings FMA, and GCC
// would otherwise fuse a * b + c, which rounds differently from the scalar code.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/geometry/tolerance.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

// Everything below (and only that: the library headers are in above) is compiled for AVX-512.
// GCC takes the target for the region by pragma; clang ignores that pragma and takes an
// attribute applied to every function defined in the region instead.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512dq"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq")
#endif
// GCC 12's AVX-512 headers pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins of _mm512_insertf64x4 and friends, which -Wuninitialized reports once inlined here.
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)  // a GCC-only warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "trocar/collision/narrow_phase_exact.h"

namespace trocar::narrow_detail {
namespace {

// Eight lanes of doubles; masks are mask registers.
struct Avx512 {
  static constexpr int kLanes = 8;
  using V = __m512d;
  using M = __mmask8;
  static V set1(double x) { return _mm512_set1_pd(x); }
  static V zero() { return _mm512_setzero_pd(); }
  static V add(V a, V b) { return _mm512_add_pd(a, b); }
  static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  static V div(V a, V b) { return _mm512_div_pd(a, b); }
  static V sqrt(V a) { return _mm512_sqrt_pd(a); }
  static V min(V a, V b) { return _mm512_min_pd(a, b); }
  static V max(V a, V b) { return _mm512_max_pd(a, b); }
  static V abs(V a) { return _mm512_abs_pd(a); }
  static M lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  static M le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
  static M and_(M a, M b) { return a & b; }
  static M or_(M a, M b) { return a | b; }
  static M xor_(M a, M b) { return a ^ b; }
  static M andnot(M a, M b) { return static_cast<M>(~a & b); }
  static V blend(V a, V b, M m) { return _mm512_mask_blend_pd(m, a, b); }  // m ? b : a
  static unsigned bits(M m) { return m; }
  static void store(double* p, V a) { _mm512_store_pd(p, a); }
  // Corner k of the eight pairs: each point by a masked 32-byte load (nothing past it is read),
  // two per register, then unpacks and 128-bit lane shuffles.
  static V two(const Vec3* lo, const Vec3* hi) {
    return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, lo->data())),
                              _mm256_maskz_loadu_pd(0x7, hi->data()), 1);
  }
  static typename Exact<Avx512>::V3 load(const Vec3* const (*c)[6], int k) {
    const __m512d a = two(c[0][k], c[2][k]);  // x0 y0 z0 0 | x2 y2 z2 0
    const __m512d b = two(c[1][k], c[3][k]);
    const __m512d e = two(c[4][k], c[6][k]);
    const __m512d f = two(c[5][k], c[7][k]);
    const __m512d xz_ab = _mm512_unpacklo_pd(a, b);  // (x0 x1) (z0 z1) (x2 x3) (z2 z3)
    const __m512d y_ab = _mm512_unpackhi_pd(a, b);
    const __m512d xz_ef = _mm512_unpacklo_pd(e, f);
    const __m512d y_ef = _mm512_unpackhi_pd(e, f);
    constexpr int kEven = _MM_SHUFFLE(2, 0, 2, 0);  // 128-bit lanes 0, 2 of each
    constexpr int kOdd = _MM_SHUFFLE(3, 1, 3, 1);
    return {_mm512_shuffle_f64x2(xz_ab, xz_ef, kEven), _mm512_shuffle_f64x2(y_ab, y_ef, kEven),
            _mm512_shuffle_f64x2(xz_ab, xz_ef, kOdd)};
  }
};

}  // namespace

int exact8_avx512(const Vec3* const (&c)[8][6], TriTriResult (&r)[8]) {
  return static_cast<int>(Exact<Avx512>::run(c, r));
}

}  // namespace trocar::narrow_detail
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

#else

namespace trocar::narrow_detail {
int exact8_avx512(const Vec3* const (&)[8][6], TriTriResult (&)[8]) { std::abort(); }
}  // namespace trocar::narrow_detail

#endif
