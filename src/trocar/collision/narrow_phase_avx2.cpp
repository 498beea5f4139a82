// The narrow phase's rejection tests for four candidates at once (AVX2 + FMA, chosen at run
// time): narrow_phase_reject.h with four lanes of __m256d and vector masks.
#include <cstdlib>
#include <limits>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

// Everything below (and only that: the library headers are in above) is compiled for AVX2 and
// FMA. GCC takes the target for the region by pragma; clang ignores that pragma and takes an
// attribute applied to every function defined in the region instead.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
#include "trocar/collision/narrow_phase_reject.h"

namespace trocar::narrow_detail {
namespace {

// Four lanes of doubles; masks are all-ones or all-zeros lanes.
struct Avx2Fma {
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
  static V fmadd(V a, V b, V c) { return _mm256_fmadd_pd(a, b, c); }
  static V fmsub(V a, V b, V c) { return _mm256_fmsub_pd(a, b, c); }
  static M gt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
  static M ge(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
  static M le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
  static M and_(M a, M b) { return _mm256_and_pd(a, b); }
  static M or_(M a, M b) { return _mm256_or_pd(a, b); }
  static M andnot(M a, M b) { return _mm256_andnot_pd(a, b); }
  static V blend(V a, V b, M m) { return _mm256_blendv_pd(a, b, m); }
  static unsigned bits(M m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
  // Four masked 32-byte loads (the fourth lane is not read, so nothing past a positions array is
  // touched) and a 4 × 4 transpose; cheaper than gathers here.
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

int reject4_avx2(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs) {
  return static_cast<int>(Reject<Avx2Fma>::run(oa, ob, pairs));
}

}  // namespace trocar::narrow_detail
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

#else

namespace trocar::narrow_detail {
int reject4_avx2(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx2_fma() is false
}
}  // namespace trocar::narrow_detail

#endif
