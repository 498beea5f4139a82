#pragma once
/// Internal to the narrow phase: the four-lane AVX2 table of vector operations that
/// narrow_phase_reject.h and narrow_phase_exact.h are written over. Included only by
/// narrow_phase_avx2.cpp and narrow_phase_exact_avx2.cpp, inside their AVX2 target regions
/// (hence the unnamed namespace: each file compiles it for its own target and flags). fmadd and
/// fmsub are templates, so a file compiled without FMA (the exact test) can include it as long as
/// it does not call them.
#include <immintrin.h>

namespace trocar::narrow_detail {
namespace {

// Four lanes of doubles; masks are all-ones or all-zeros lanes.
struct Lanes4 {
  static constexpr int kLanes = 4;
  using V = __m256d;
  using M = __m256d;
  static V set1(double x) { return _mm256_set1_pd(x); }
  static V zero() { return _mm256_setzero_pd(); }
  static V add(V a, V b) { return _mm256_add_pd(a, b); }
  static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  static V div(V a, V b) { return _mm256_div_pd(a, b); }
  static V sqrt(V a) { return _mm256_sqrt_pd(a); }
  static V min(V a, V b) { return _mm256_min_pd(a, b); }
  static V max(V a, V b) { return _mm256_max_pd(a, b); }
  static V abs(V a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
  template <class T = V>
  static T fmadd(T a, T b, T c) {  // a·b + c
    return _mm256_fmadd_pd(a, b, c);
  }
  template <class T = V>
  static T fmsub(T a, T b, T c) {  // a·b − c
    return _mm256_fmsub_pd(a, b, c);
  }
  static M lt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  static M le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
  static M gt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
  static M ge(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
  static M and_(M a, M b) { return _mm256_and_pd(a, b); }
  static M or_(M a, M b) { return _mm256_or_pd(a, b); }
  static M xor_(M a, M b) { return _mm256_xor_pd(a, b); }
  static M andnot(M a, M b) { return _mm256_andnot_pd(a, b); }  // ~a & b
  static V blend(V a, V b, M m) { return _mm256_blendv_pd(a, b, m); }  // m ? b : a
  static unsigned bits(M m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
  static void store(double* p, V a) { _mm256_store_pd(p, a); }
  // Four points (three doubles each) as x, y, z vectors: four masked 32-byte loads (the fourth
  // lane is not read, so nothing past a point is touched) and a 4 × 4 transpose; cheaper than
  // gathers here.
  static void load(const double* const (&p)[4], V& x, V& y, V& z) {
    const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
    const __m256d r0 = _mm256_maskload_pd(p[0], xyz);  // x0 y0 z0 0
    const __m256d r1 = _mm256_maskload_pd(p[1], xyz);
    const __m256d r2 = _mm256_maskload_pd(p[2], xyz);
    const __m256d r3 = _mm256_maskload_pd(p[3], xyz);
    const __m256d xz01 = _mm256_unpacklo_pd(r0, r1);  // x0 x1 z0 z1
    const __m256d y01 = _mm256_unpackhi_pd(r0, r1);   // y0 y1 0 0
    const __m256d xz23 = _mm256_unpacklo_pd(r2, r3);
    const __m256d y23 = _mm256_unpackhi_pd(r2, r3);
    x = _mm256_permute2f128_pd(xz01, xz23, 0x20);
    y = _mm256_permute2f128_pd(y01, y23, 0x20);
    z = _mm256_permute2f128_pd(xz01, xz23, 0x31);
  }
};

}  // namespace
}  // namespace trocar::narrow_detail
