// The narrow phase's rejection tests for four candidates at once (AVX2 + FMA, chosen at run
// time). Lane k holds candidate k: its corners are loaded from the positions, and the tests of
// the portable path (narrow_phase.cpp) run on all four lanes — A's plane against B's corners, B's
// plane against A's corners (each with the conservative 1e-9·L margin), then the interval test
// on the line nA × nB (Möller, "A Fast Triangle-Triangle Intersection Test", JGT 1997, made
// conservative as there). The candidates no test rejects go on to the exact test (narrow_phase.cpp
// batches them).
// FMA and one reciprocal per edge round differently from the portable path by a few ulp, which
// the margins (orders of magnitude wider) absorb: both paths reject only pairs the exact test
// rejects, so the contacts are the same.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TROCAR_NARROW_AVX2 1
#endif

namespace trocar::narrow_detail {

#if defined(TROCAR_NARROW_AVX2)
namespace {

#define TROCAR_AVX2 __attribute__((target("avx2,fma"), always_inline)) inline

struct V3 {
  __m256d x, y, z;
};

TROCAR_AVX2 V3 sub(const V3& a, const V3& b) {
  return {_mm256_sub_pd(a.x, b.x), _mm256_sub_pd(a.y, b.y), _mm256_sub_pd(a.z, b.z)};
}
TROCAR_AVX2 __m256d dot(const V3& a, const V3& b) {
  return _mm256_fmadd_pd(a.x, b.x, _mm256_fmadd_pd(a.y, b.y, _mm256_mul_pd(a.z, b.z)));
}
TROCAR_AVX2 V3 cross(const V3& a, const V3& b) {
  return {_mm256_fmsub_pd(a.y, b.z, _mm256_mul_pd(a.z, b.y)), _mm256_fmsub_pd(a.z, b.x, _mm256_mul_pd(a.x, b.z)),
          _mm256_fmsub_pd(a.x, b.y, _mm256_mul_pd(a.y, b.x))};
}
// Four points (x, y, z each) as x, y, z vectors: four masked 32-byte loads (the fourth lane is
// not read, so nothing past a positions array is touched) and a 4 × 4 transpose; cheaper than
// gathers here.
TROCAR_AVX2 V3 load4(const double* p0, const double* p1, const double* p2, const double* p3) {
  const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
  const __m256d r0 = _mm256_maskload_pd(p0, xyz);  // x0 y0 z0 0
  const __m256d r1 = _mm256_maskload_pd(p1, xyz);
  const __m256d r2 = _mm256_maskload_pd(p2, xyz);
  const __m256d r3 = _mm256_maskload_pd(p3, xyz);
  const __m256d xz01 = _mm256_unpacklo_pd(r0, r1);  // x0 x1 z0 z1
  const __m256d y01 = _mm256_unpackhi_pd(r0, r1);   // y0 y1 0 0
  const __m256d xz23 = _mm256_unpacklo_pd(r2, r3);
  const __m256d y23 = _mm256_unpackhi_pd(r2, r3);
  return {_mm256_permute2f128_pd(xz01, xz23, 0x20), _mm256_permute2f128_pd(y01, y23, 0x20),
          _mm256_permute2f128_pd(xz01, xz23, 0x31)};
}
// Corner c of four triangles.
TROCAR_AVX2 V3 corner(const Vec3* p, const Triangle* const (&t)[4], int c) {
  return load4(p[(*t[0])[c]].data(), p[(*t[1])[c]].data(), p[(*t[2])[c]].data(), p[(*t[3])[c]].data());
}
TROCAR_AVX2 __m256d gt(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
TROCAR_AVX2 __m256d both(__m256d a, __m256d b) { return _mm256_and_pd(a, b); }

// The plane of a triangle with edges e1, e2 (and e2 − e1): normal, |n|², well-shaped mask.
struct Plane4 {
  V3 n;
  __m256d n2;
  __m256d well;
};
TROCAR_AVX2 Plane4 plane4(const V3& e1, const V3& e2) {
  Plane4 p;
  p.n = cross(e1, e2);
  p.n2 = dot(p.n, p.n);
  const V3 e3 = sub(e2, e1);
  const __m256d longest2 = _mm256_max_pd(_mm256_max_pd(dot(e1, e1), dot(e2, e2)), dot(e3, e3));
  p.well = gt(p.n2, _mm256_mul_pd(_mm256_set1_pd(1e-6), _mm256_mul_pd(longest2, longest2)));
  return p;
}

// Mask of the lanes whose three distances d (× |n|) lie strictly on one side of a well-shaped
// plane by more than 1e-9·L: d_i² > 1e-18·L²·|n|² (as separated_by_plane in narrow_phase.cpp).
TROCAR_AVX2 __m256d separated(const Plane4& p, __m256d d0, __m256d d1, __m256d d2, __m256d size2) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d above = both(both(gt(d0, zero), gt(d1, zero)), gt(d2, zero));
  const __m256d below = both(both(gt(zero, d0), gt(zero, d1)), gt(zero, d2));
  const __m256d threshold2 = _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(1e-18), size2), p.n2);
  const __m256d far = both(both(gt(_mm256_mul_pd(d0, d0), threshold2), gt(_mm256_mul_pd(d1, d1), threshold2)),
                           gt(_mm256_mul_pd(d2, d2), threshold2));
  return both(both(p.well, _mm256_or_pd(above, below)), far);
}

// The projections on the line of the parts of a triangle within the slab |d| ≤ tau of the other
// plane, edge by edge (as slab_interval in narrow_phase.cpp): [lo, hi] per lane.
struct Interval4 {
  __m256d lo;  // +inf when empty
  __m256d hi;  // −inf when empty

  TROCAR_AVX2 void clear() {
    lo = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    hi = _mm256_set1_pd(-std::numeric_limits<double>::infinity());
  }

  // Edge from corner i (projection pi, distance di) to corner j.
  TROCAR_AVX2 void edge(__m256d pi, __m256d pj, __m256d di, __m256d dj, __m256d tau) {
    const __m256d neg_tau = _mm256_sub_pd(_mm256_setzero_pd(), tau);
    const __m256d outside = _mm256_or_pd(both(gt(di, tau), gt(dj, tau)), both(gt(neg_tau, di), gt(neg_tau, dj)));
    const __m256d dd = _mm256_sub_pd(dj, di);
    const __m256d abs_dd = _mm256_andnot_pd(_mm256_set1_pd(-0.0), dd);
    const __m256d steep = gt(abs_dd, tau);
    // d(λ) = di + λ·dd ∈ [−tau, tau] for λ between a and b (only where the edge is steep).
    // One division for both (a reciprocal rounds differently from the portable path's two
    // divisions, by a few ulp: nothing next to the slab's 1e-9·L).
    const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), dd);
    const __m256d a = _mm256_mul_pd(_mm256_sub_pd(neg_tau, di), inv);
    const __m256d b = _mm256_mul_pd(_mm256_sub_pd(tau, di), inv);
    const __m256d zero = _mm256_setzero_pd();
    const __m256d one = _mm256_set1_pd(1.0);
    __m256d l0 = _mm256_blendv_pd(zero, _mm256_max_pd(zero, _mm256_min_pd(a, b)), steep);
    __m256d l1 = _mm256_blendv_pd(one, _mm256_min_pd(one, _mm256_max_pd(a, b)), steep);
    // l0 > l1 only by rounding (the edge just reaches the slab): keep the middle, in [0, 1].
    const __m256d crossed = gt(l0, l1);
    const __m256d mid = _mm256_min_pd(one, _mm256_max_pd(zero, _mm256_mul_pd(_mm256_set1_pd(0.5), _mm256_add_pd(l0, l1))));
    l0 = _mm256_blendv_pd(l0, mid, crossed);
    l1 = _mm256_blendv_pd(l1, mid, crossed);
    const __m256d span = _mm256_sub_pd(pj, pi);
    const __m256d x0 = _mm256_fmadd_pd(l0, span, pi);
    const __m256d x1 = _mm256_fmadd_pd(l1, span, pi);
    lo = _mm256_blendv_pd(_mm256_min_pd(lo, _mm256_min_pd(x0, x1)), lo, outside);
    hi = _mm256_blendv_pd(_mm256_max_pd(hi, _mm256_max_pd(x0, x1)), hi, outside);
  }
};

}  // namespace

__attribute__((target("avx2,fma"))) int reject4_avx2(const CollisionObject& oa, const CollisionObject& ob,
                                                          const CandidatePair* pairs) {
  const Vec3* pa = oa.positions.data();
  const Vec3* pb = ob.positions.data();
  const Triangle* ta[4];
  const Triangle* tb[4];
  for (int k = 0; k < 4; ++k) {
    ta[k] = &oa.triangles[pairs[k].triangle_a];
    tb[k] = &ob.triangles[pairs[k].triangle_b];
  }
  const V3 a0 = corner(pa, ta, 0);
  const V3 ra1 = sub(corner(pa, ta, 1), a0);
  const V3 ra2 = sub(corner(pa, ta, 2), a0);
  const V3 rb0 = sub(corner(pb, tb, 0), a0);
  const V3 rb1 = sub(corner(pb, tb, 1), a0);
  const V3 rb2 = sub(corner(pb, tb, 2), a0);

  // The pair's size L (a0 is the origin, so 0 is one of the six corners).
  const __m256d zero = _mm256_setzero_pd();
  __m256d lo_x = zero, lo_y = zero, lo_z = zero, hi_x = zero, hi_y = zero, hi_z = zero;
  for (const V3* c : {&ra1, &ra2, &rb0, &rb1, &rb2}) {
    lo_x = _mm256_min_pd(lo_x, c->x);
    lo_y = _mm256_min_pd(lo_y, c->y);
    lo_z = _mm256_min_pd(lo_z, c->z);
    hi_x = _mm256_max_pd(hi_x, c->x);
    hi_y = _mm256_max_pd(hi_y, c->y);
    hi_z = _mm256_max_pd(hi_z, c->z);
  }
  const __m256d size = _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(hi_x, lo_x), _mm256_sub_pd(hi_y, lo_y)),
                                     _mm256_sub_pd(hi_z, lo_z));
  const __m256d finite = _mm256_cmp_pd(size, _mm256_set1_pd(std::numeric_limits<double>::infinity()), _CMP_LT_OQ);
  const __m256d size2 = _mm256_mul_pd(size, size);

  const Plane4 plane_a = plane4(ra1, ra2);
  const __m256d db0 = dot(plane_a.n, rb0);
  const __m256d db1 = dot(plane_a.n, rb1);
  const __m256d db2 = dot(plane_a.n, rb2);
  const __m256d sep_a = separated(plane_a, db0, db1, db2, size2);
  const Plane4 plane_b = plane4(sub(rb1, rb0), sub(rb2, rb0));
  const __m256d da0 = _mm256_sub_pd(zero, dot(plane_b.n, rb0));
  const __m256d da1 = dot(plane_b.n, sub(ra1, rb0));
  const __m256d da2 = dot(plane_b.n, sub(ra2, rb0));
  const __m256d sep_b = separated(plane_b, da0, da1, da2, size2);
  const __m256d planes_keep = _mm256_andnot_pd(_mm256_or_pd(sep_a, sep_b), finite);
  if (_mm256_movemask_pd(planes_keep) == 0) return 0;

  // The interval test on the lanes the planes kept (as separated_on_line in narrow_phase.cpp).
  const V3 dir = cross(plane_a.n, plane_b.n);
  const __m256d dir2 = dot(dir, dir);
  const __m256d line_ok =
      both(both(plane_a.well, plane_b.well),
           _mm256_cmp_pd(dir2, _mm256_mul_pd(_mm256_set1_pd(1e-4), _mm256_mul_pd(plane_a.n2, plane_b.n2)), _CMP_GE_OQ));
  const __m256d eps_size = _mm256_mul_pd(_mm256_set1_pd(1e-9), size);
  Interval4 ia4;
  ia4.clear();
  const __m256d tau_a = _mm256_mul_pd(eps_size, _mm256_sqrt_pd(plane_b.n2));
  const __m256d pa1 = dot(dir, ra1);
  const __m256d pa2 = dot(dir, ra2);
  ia4.edge(zero, pa1, da0, da1, tau_a);
  ia4.edge(pa1, pa2, da1, da2, tau_a);
  ia4.edge(pa2, zero, da2, da0, tau_a);
  Interval4 ib4;
  ib4.clear();
  const __m256d tau_b = _mm256_mul_pd(eps_size, _mm256_sqrt_pd(plane_a.n2));
  const __m256d pb0 = dot(dir, rb0);
  const __m256d pb1 = dot(dir, rb1);
  const __m256d pb2 = dot(dir, rb2);
  ib4.edge(pb0, pb1, db0, db1, tau_b);
  ib4.edge(pb1, pb2, db1, db2, tau_b);
  ib4.edge(pb2, pb0, db2, db0, tau_b);
  const __m256d nonempty = both(_mm256_cmp_pd(ia4.lo, ia4.hi, _CMP_LE_OQ), _mm256_cmp_pd(ib4.lo, ib4.hi, _CMP_LE_OQ));
  const __m256d gap = _mm256_sub_pd(_mm256_max_pd(ia4.lo, ib4.lo), _mm256_min_pd(ia4.hi, ib4.hi));
  const __m256d apart = both(gt(gap, zero), gt(_mm256_mul_pd(gap, gap), _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(1e-14), size2), dir2)));
  const __m256d sep_line = both(both(line_ok, nonempty), apart);
  return _mm256_movemask_pd(_mm256_andnot_pd(sep_line, planes_keep));
}

#else

int reject4_avx2(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx2_fma() is false
}

#endif

}  // namespace trocar::narrow_detail
