// exact4_avx2: the narrow phase's exact test on four pairs at once (narrow_phase_exact.h) with
// AVX2, compiled without FMA (a target of AVX2 alone, and -ffp-contract=off from CMakeLists.txt):
// GCC's intrinsics are plain vector arithmetic, which it would otherwise fuse into a * b + c.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/geometry/tolerance.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

// Everything below (and only that: the library headers are in above) is compiled for AVX2.
// GCC takes the target for the region by pragma; clang ignores that pragma and takes an
// attribute applied to every function defined in the region instead.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
#include "trocar/collision/narrow_phase_exact.h"

namespace trocar::narrow_detail {
namespace {

// Four lanes of doubles; masks are all-ones or all-zeros lanes.
struct Avx2 {
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
  static M lt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  static M le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
  static M and_(M a, M b) { return _mm256_and_pd(a, b); }
  static M or_(M a, M b) { return _mm256_or_pd(a, b); }
  static M xor_(M a, M b) { return _mm256_xor_pd(a, b); }
  static M andnot(M a, M b) { return _mm256_andnot_pd(a, b); }  // ~a & b
  static V blend(V a, V b, M m) { return _mm256_blendv_pd(a, b, m); }  // m ? b : a
  static unsigned bits(M m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
  static void store(double* p, V a) { _mm256_store_pd(p, a); }
  // Corner k of the four pairs: masked loads (nothing past a point is read), 4 × 4 transpose.
  static typename Exact<Avx2>::V3 load(const Vec3* const (*c)[6], int k) {
    const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
    const __m256d r0 = _mm256_maskload_pd(c[0][k]->data(), xyz);
    const __m256d r1 = _mm256_maskload_pd(c[1][k]->data(), xyz);
    const __m256d r2 = _mm256_maskload_pd(c[2][k]->data(), xyz);
    const __m256d r3 = _mm256_maskload_pd(c[3][k]->data(), xyz);
    const __m256d xz01 = _mm256_unpacklo_pd(r0, r1);
    const __m256d y01 = _mm256_unpackhi_pd(r0, r1);
    const __m256d xz23 = _mm256_unpacklo_pd(r2, r3);
    const __m256d y23 = _mm256_unpackhi_pd(r2, r3);
    return {_mm256_permute2f128_pd(xz01, xz23, 0x20), _mm256_permute2f128_pd(y01, y23, 0x20),
            _mm256_permute2f128_pd(xz01, xz23, 0x31)};
  }
};

}  // namespace

int exact4_avx2(const Vec3* const (&c)[4][6], TriTriResult (&r)[4]) {
  return static_cast<int>(Exact<Avx2>::run(c, r));
}

}  // namespace trocar::narrow_detail
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

#else

namespace trocar::narrow_detail {
int exact4_avx2(const Vec3* const (&)[4][6], TriTriResult (&)[4]) { return 0; }
}  // namespace trocar::narrow_detail

#endif
