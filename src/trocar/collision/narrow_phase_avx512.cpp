// The narrow phase's rejection tests for eight candidates at once (AVX-512, chosen at run time):
// reject4_avx2 (narrow_phase_avx2.cpp) with eight lanes and mask registers, the same tests in the
// same order with the same margins. Eight lanes halve the arithmetic per candidate, and 32
// registers hold what the four-lane version spills.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TROCAR_NARROW_AVX512 1
// GCC 12's own AVX-512 headers pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins of _mm512_insertf64x4 and friends, which -Wuninitialized reports once inlined here.
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)  // a GCC-only warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#endif

namespace trocar::narrow_detail {

#if defined(TROCAR_NARROW_AVX512)
namespace {

#define TROCAR_AVX512 __attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"), always_inline)) inline

struct W3 {
  __m512d x, y, z;
};

TROCAR_AVX512 W3 sub(const W3& a, const W3& b) {
  return {_mm512_sub_pd(a.x, b.x), _mm512_sub_pd(a.y, b.y), _mm512_sub_pd(a.z, b.z)};
}
TROCAR_AVX512 __m512d dot(const W3& a, const W3& b) {
  return _mm512_fmadd_pd(a.x, b.x, _mm512_fmadd_pd(a.y, b.y, _mm512_mul_pd(a.z, b.z)));
}
TROCAR_AVX512 W3 cross(const W3& a, const W3& b) {
  return {_mm512_fmsub_pd(a.y, b.z, _mm512_mul_pd(a.z, b.y)), _mm512_fmsub_pd(a.z, b.x, _mm512_mul_pd(a.x, b.z)),
          _mm512_fmsub_pd(a.x, b.y, _mm512_mul_pd(a.y, b.x))};
}
TROCAR_AVX512 __mmask8 gt(__m512d a, __m512d b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }

// Eight points as x, y, z vectors: each point by a masked 32-byte load (its three coordinates;
// nothing past it is read), two points per 512-bit register, then unpacks and lane shuffles.
TROCAR_AVX512 __m512d pair(const double* lo, const double* hi) {
  return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, lo)), _mm256_maskz_loadu_pd(0x7, hi), 1);
}
TROCAR_AVX512 W3 load8(const double* const (&p)[8]) {
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
  return {_mm512_shuffle_f64x2(xz_ab, xz_cd, kEven), _mm512_shuffle_f64x2(y_ab, y_cd, kEven),
          _mm512_shuffle_f64x2(xz_ab, xz_cd, kOdd)};
}
// Corner c of eight triangles.
TROCAR_AVX512 W3 corner(const Vec3* p, const Triangle* const (&t)[8], int c) {
  const double* q[8];
  for (int k = 0; k < 8; ++k) q[k] = p[(*t[k])[c]].data();
  return load8(q);
}

struct Plane8 {
  W3 n;
  __m512d n2;
  __mmask8 well;
};
TROCAR_AVX512 Plane8 plane8(const W3& e1, const W3& e2) {
  Plane8 p;
  p.n = cross(e1, e2);
  p.n2 = dot(p.n, p.n);
  const W3 e3 = sub(e2, e1);
  const __m512d longest2 = _mm512_max_pd(_mm512_max_pd(dot(e1, e1), dot(e2, e2)), dot(e3, e3));
  p.well = gt(p.n2, _mm512_mul_pd(_mm512_set1_pd(1e-6), _mm512_mul_pd(longest2, longest2)));
  return p;
}

// The lanes whose three distances lie strictly on one side of a well-shaped plane by more than
// 1e-9·L (separated() in narrow_phase_avx2.cpp).
TROCAR_AVX512 __mmask8 separated(const Plane8& p, __m512d d0, __m512d d1, __m512d d2, __m512d size2) {
  const __m512d zero = _mm512_setzero_pd();
  const __mmask8 above = gt(d0, zero) & gt(d1, zero) & gt(d2, zero);
  const __mmask8 below = gt(zero, d0) & gt(zero, d1) & gt(zero, d2);
  const __m512d threshold2 = _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(1e-18), size2), p.n2);
  const __mmask8 far = gt(_mm512_mul_pd(d0, d0), threshold2) & gt(_mm512_mul_pd(d1, d1), threshold2) &
                       gt(_mm512_mul_pd(d2, d2), threshold2);
  return p.well & (above | below) & far;
}

// Interval4 of narrow_phase_avx2.cpp, eight lanes.
struct Interval8 {
  __m512d lo;  // +inf when empty
  __m512d hi;  // −inf when empty

  TROCAR_AVX512 void clear() {
    lo = _mm512_set1_pd(std::numeric_limits<double>::infinity());
    hi = _mm512_set1_pd(-std::numeric_limits<double>::infinity());
  }

  TROCAR_AVX512 void edge(__m512d pi, __m512d pj, __m512d di, __m512d dj, __m512d tau) {
    const __m512d neg_tau = _mm512_sub_pd(_mm512_setzero_pd(), tau);
    const __mmask8 outside = (gt(di, tau) & gt(dj, tau)) | (gt(neg_tau, di) & gt(neg_tau, dj));
    const __m512d dd = _mm512_sub_pd(dj, di);
    const __mmask8 steep = gt(_mm512_abs_pd(dd), tau);
    const __m512d inv = _mm512_div_pd(_mm512_set1_pd(1.0), dd);
    const __m512d a = _mm512_mul_pd(_mm512_sub_pd(neg_tau, di), inv);
    const __m512d b = _mm512_mul_pd(_mm512_sub_pd(tau, di), inv);
    const __m512d zero = _mm512_setzero_pd();
    const __m512d one = _mm512_set1_pd(1.0);
    __m512d l0 = _mm512_mask_blend_pd(steep, zero, _mm512_max_pd(zero, _mm512_min_pd(a, b)));
    __m512d l1 = _mm512_mask_blend_pd(steep, one, _mm512_min_pd(one, _mm512_max_pd(a, b)));
    const __mmask8 crossed = gt(l0, l1);
    const __m512d half_sum = _mm512_mul_pd(_mm512_set1_pd(0.5), _mm512_add_pd(l0, l1));
    const __m512d mid = _mm512_min_pd(one, _mm512_max_pd(zero, half_sum));
    l0 = _mm512_mask_blend_pd(crossed, l0, mid);
    l1 = _mm512_mask_blend_pd(crossed, l1, mid);
    const __m512d span = _mm512_sub_pd(pj, pi);
    const __m512d x0 = _mm512_fmadd_pd(l0, span, pi);
    const __m512d x1 = _mm512_fmadd_pd(l1, span, pi);
    lo = _mm512_mask_blend_pd(outside, _mm512_min_pd(lo, _mm512_min_pd(x0, x1)), lo);
    hi = _mm512_mask_blend_pd(outside, _mm512_max_pd(hi, _mm512_max_pd(x0, x1)), hi);
  }
};

}  // namespace

__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) int reject8_avx512(const CollisionObject& oa,
                                                                               const CollisionObject& ob,
                                                                               const CandidatePair* pairs) {
  const Vec3* pa = oa.positions.data();
  const Vec3* pb = ob.positions.data();
  const Triangle* ta[8];
  const Triangle* tb[8];
  for (int k = 0; k < 8; ++k) {
    ta[k] = &oa.triangles[pairs[k].triangle_a];
    tb[k] = &ob.triangles[pairs[k].triangle_b];
  }
  const W3 a0 = corner(pa, ta, 0);
  const W3 ra1 = sub(corner(pa, ta, 1), a0);
  const W3 ra2 = sub(corner(pa, ta, 2), a0);
  const W3 rb0 = sub(corner(pb, tb, 0), a0);
  const W3 rb1 = sub(corner(pb, tb, 1), a0);
  const W3 rb2 = sub(corner(pb, tb, 2), a0);

  // The pair's size L (a0 is the origin, so 0 is one of the six corners).
  const __m512d zero = _mm512_setzero_pd();
  __m512d lo_x = zero, lo_y = zero, lo_z = zero, hi_x = zero, hi_y = zero, hi_z = zero;
  for (const W3* c : {&ra1, &ra2, &rb0, &rb1, &rb2}) {
    lo_x = _mm512_min_pd(lo_x, c->x);
    lo_y = _mm512_min_pd(lo_y, c->y);
    lo_z = _mm512_min_pd(lo_z, c->z);
    hi_x = _mm512_max_pd(hi_x, c->x);
    hi_y = _mm512_max_pd(hi_y, c->y);
    hi_z = _mm512_max_pd(hi_z, c->z);
  }
  const __m512d size = _mm512_max_pd(_mm512_max_pd(_mm512_sub_pd(hi_x, lo_x), _mm512_sub_pd(hi_y, lo_y)),
                                     _mm512_sub_pd(hi_z, lo_z));
  const __mmask8 finite = _mm512_cmp_pd_mask(size, _mm512_set1_pd(std::numeric_limits<double>::infinity()), _CMP_LT_OQ);
  const __m512d size2 = _mm512_mul_pd(size, size);

  const Plane8 plane_a = plane8(ra1, ra2);
  const __m512d db0 = dot(plane_a.n, rb0);
  const __m512d db1 = dot(plane_a.n, rb1);
  const __m512d db2 = dot(plane_a.n, rb2);
  const __mmask8 sep_a = separated(plane_a, db0, db1, db2, size2);
  const Plane8 plane_b = plane8(sub(rb1, rb0), sub(rb2, rb0));
  const __m512d da0 = _mm512_sub_pd(zero, dot(plane_b.n, rb0));
  const __m512d da1 = dot(plane_b.n, sub(ra1, rb0));
  const __m512d da2 = dot(plane_b.n, sub(ra2, rb0));
  const __mmask8 sep_b = separated(plane_b, da0, da1, da2, size2);
  const __mmask8 planes_keep = static_cast<__mmask8>(finite & ~(sep_a | sep_b));
  if (planes_keep == 0) return 0;

  // The interval test on the line nA × nB (separated_on_line in narrow_phase.cpp).
  const W3 dir = cross(plane_a.n, plane_b.n);
  const __m512d dir2 = dot(dir, dir);
  const __m512d min_dir2 = _mm512_mul_pd(_mm512_set1_pd(1e-4), _mm512_mul_pd(plane_a.n2, plane_b.n2));
  const __mmask8 line_ok = plane_a.well & plane_b.well & _mm512_cmp_pd_mask(dir2, min_dir2, _CMP_GE_OQ);
  const __m512d eps_size = _mm512_mul_pd(_mm512_set1_pd(1e-9), size);
  Interval8 ia;
  ia.clear();
  const __m512d tau_a = _mm512_mul_pd(eps_size, _mm512_sqrt_pd(plane_b.n2));
  const __m512d pa1 = dot(dir, ra1);
  const __m512d pa2 = dot(dir, ra2);
  ia.edge(zero, pa1, da0, da1, tau_a);
  ia.edge(pa1, pa2, da1, da2, tau_a);
  ia.edge(pa2, zero, da2, da0, tau_a);
  Interval8 ib;
  ib.clear();
  const __m512d tau_b = _mm512_mul_pd(eps_size, _mm512_sqrt_pd(plane_a.n2));
  const __m512d pb0 = dot(dir, rb0);
  const __m512d pb1 = dot(dir, rb1);
  const __m512d pb2 = dot(dir, rb2);
  ib.edge(pb0, pb1, db0, db1, tau_b);
  ib.edge(pb1, pb2, db1, db2, tau_b);
  ib.edge(pb2, pb0, db2, db0, tau_b);
  const __mmask8 nonempty = _mm512_cmp_pd_mask(ia.lo, ia.hi, _CMP_LE_OQ) & _mm512_cmp_pd_mask(ib.lo, ib.hi, _CMP_LE_OQ);
  const __m512d gap = _mm512_sub_pd(_mm512_max_pd(ia.lo, ib.lo), _mm512_min_pd(ia.hi, ib.hi));
  const __mmask8 apart =
      gt(gap, zero) & gt(_mm512_mul_pd(gap, gap), _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(1e-14), size2), dir2));
  return planes_keep & ~(line_ok & nonempty & apart) & 0xff;
}

#else

int reject8_avx512(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx512() is false
}

#endif

}  // namespace trocar::narrow_detail
