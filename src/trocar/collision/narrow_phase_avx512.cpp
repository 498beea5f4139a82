// The narrow phase's rejection tests for eight candidates at once (AVX-512, chosen at run time):
// narrow_phase_reject.h with eight lanes of __m512d and mask registers, the same tests in the
// same order with the same margins as the four-lane AVX2 version. Eight lanes halve the
// arithmetic per candidate, and 32 registers hold what the four-lane version spills.
#include <cstdlib>
#include <limits>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

// Everything below (and only that: the library headers are in above) is compiled for AVX-512
// (with AVX2 and FMA). GCC takes the target for the region by pragma; clang ignores that pragma
// and takes an attribute applied to every function defined in the region instead.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq,avx2,fma")
#endif
// GCC 12's own AVX-512 headers pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins of _mm512_insertf64x4 and friends, which -Wuninitialized reports once inlined here.
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)  // a GCC-only warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "trocar/collision/narrow_phase_reject.h"

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
  static V fmadd(V a, V b, V c) { return _mm512_fmadd_pd(a, b, c); }
  static V fmsub(V a, V b, V c) { return _mm512_fmsub_pd(a, b, c); }
  static M gt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
  static M ge(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
  static M le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
  static M and_(M a, M b) { return static_cast<M>(a & b); }
  static M or_(M a, M b) { return static_cast<M>(a | b); }
  static M andnot(M a, M b) { return static_cast<M>(~a & b); }
  static V blend(V a, V b, M m) { return _mm512_mask_blend_pd(m, a, b); }
  static unsigned bits(M m) { return m; }
  // Each point by a masked 32-byte load (its three coordinates; nothing past it is read), two
  // points per 512-bit register, then unpacks and lane shuffles.
  static V pair(const double* lo, const double* hi) {
    return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, lo)), _mm256_maskz_loadu_pd(0x7, hi),
                              1);
  }
  static void load(const double* const (&p)[8], V& x, V& y, V& z) {
    const __m512d a = pair(p[0], p[2]);  // x0 y0 z0 0 | x2 y2 z2 0
    const __m512d b = pair(p[1], p[3]);
    const __m512d c = pair(p[4], p[6]);
    const __m512d d = pair(p[5], p[7]);
    const __m512d xz_ab = _mm512_unpacklo_pd(a, b);  // (x0 x1) (z0 z1) (x2 x3) (z2 z3)
    const __m512d y_ab = _mm512_unpackhi_pd(a, b);   // (y0 y1) (0 0) (y2 y3) (0 0)
    const __m512d xz_cd = _mm512_unpacklo_pd(c, d);
    const __m512d y_cd = _mm512_unpackhi_pd(c, d);
    constexpr int kEven = _MM_SHUFFLE(2, 0, 2, 0);  // 128-bit lanes 0, 2 of each
    constexpr int kOdd = _MM_SHUFFLE(3, 1, 3, 1);
    x = _mm512_shuffle_f64x2(xz_ab, xz_cd, kEven);
    y = _mm512_shuffle_f64x2(y_ab, y_cd, kEven);
    z = _mm512_shuffle_f64x2(xz_ab, xz_cd, kOdd);
  }
};

}  // namespace

int reject8_avx512(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs) {
  return static_cast<int>(Reject<Avx512>::run(oa, ob, pairs));
}

}  // namespace trocar::narrow_detail
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

#else

namespace trocar::narrow_detail {
int reject8_avx512(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx512() is false
}
}  // namespace trocar::narrow_detail

#endif
