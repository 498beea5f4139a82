#pragma once
/// Internal to the narrow phase: the eight-lane AVX-512 table of vector operations that
/// narrow_phase_reject.h and narrow_phase_exact.h are written over. Included only by
/// narrow_phase_avx512.cpp and narrow_phase_exact_avx512.cpp, inside their AVX-512 target regions
/// (hence the unnamed namespace: each file compiles it for its own target and flags). fmadd and
/// fmsub are templates, so a file compiled without FMA contraction (the exact test) can include
/// it as long as it does not call them.
#include <immintrin.h>

namespace trocar::narrow_detail {
namespace {

// Eight lanes of doubles; masks are mask registers.
struct Lanes8 {
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
  template <class T = V>
  static T fmadd(T a, T b, T c) {  // a·b + c
    return _mm512_fmadd_pd(a, b, c);
  }
  template <class T = V>
  static T fmsub(T a, T b, T c) {  // a·b − c
    return _mm512_fmsub_pd(a, b, c);
  }
  static M lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  static M le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
  static M gt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
  static M ge(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
  static M and_(M a, M b) { return static_cast<M>(a & b); }
  static M or_(M a, M b) { return static_cast<M>(a | b); }
  static M xor_(M a, M b) { return static_cast<M>(a ^ b); }
  static M andnot(M a, M b) { return static_cast<M>(~a & b); }
  static V blend(V a, V b, M m) { return _mm512_mask_blend_pd(m, a, b); }  // m ? b : a
  static unsigned bits(M m) { return m; }
  static void store(double* p, V a) { _mm512_store_pd(p, a); }
  // Two points (three doubles each) in one register, each by a masked 32-byte load (nothing past
  // it is read).
  static V two(const double* lo, const double* hi) {
    return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, lo)), _mm256_maskz_loadu_pd(0x7, hi),
                              1);
  }
  // Eight points as x, y, z vectors: two per register, then unpacks and 128-bit lane shuffles.
  static void load(const double* const (&p)[8], V& x, V& y, V& z) {
    const __m512d a = two(p[0], p[2]);  // x0 y0 z0 0 | x2 y2 z2 0
    const __m512d b = two(p[1], p[3]);
    const __m512d c = two(p[4], p[6]);
    const __m512d d = two(p[5], p[7]);
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
}  // namespace trocar::narrow_detail
