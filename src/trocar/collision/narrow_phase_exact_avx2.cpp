// intersect_triangles (src/trocar/geometry/triangle_triangle.cpp) on four pairs at once, bit for
// bit, for the common case: both triangles proper, finite, crossing each other's plane with no
// vertex within the tolerance of the other plane. Every other lane (coplanar, degenerate, a
// vertex on the other plane, two single-point traces, non-finite input) is left to the scalar
// function. Each lane runs the scalar code's operations in the scalar
// code's order (Eigen's dot and squaredNorm sum x, y, then z; cross products by the textbook
// formula; divisions, not reciprocals), compiled for AVX2 without FMA so that nothing can be
// contracted: IEEE arithmetic is then the same in a lane as in a scalar register. Branches
// become blends (all sides are computed; the unused ones may be inf or NaN and are dropped).
// narrow_phase_test.cpp checks the results against intersect_triangles bit for bit.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/geometry/tolerance.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TROCAR_EXACT_AVX2 1
#endif

namespace trocar::narrow_detail {

#if defined(TROCAR_EXACT_AVX2)
namespace {

// No "fma" here: with it GCC may fuse a * b + c (its intrinsics are plain vector arithmetic).
#define TROCAR_AVX2_EXACT __attribute__((target("avx2"), always_inline)) inline

struct V3 {
  __m256d x, y, z;
};

TROCAR_AVX2_EXACT V3 sub(const V3& a, const V3& b) {
  return {_mm256_sub_pd(a.x, b.x), _mm256_sub_pd(a.y, b.y), _mm256_sub_pd(a.z, b.z)};
}
TROCAR_AVX2_EXACT V3 add(const V3& a, const V3& b) {
  return {_mm256_add_pd(a.x, b.x), _mm256_add_pd(a.y, b.y), _mm256_add_pd(a.z, b.z)};
}
TROCAR_AVX2_EXACT V3 scale(__m256d s, const V3& a) {
  return {_mm256_mul_pd(s, a.x), _mm256_mul_pd(s, a.y), _mm256_mul_pd(s, a.z)};
}
TROCAR_AVX2_EXACT V3 divide(const V3& a, __m256d s) {
  return {_mm256_div_pd(a.x, s), _mm256_div_pd(a.y, s), _mm256_div_pd(a.z, s)};
}
// (x·x + y·y) + z·z, Eigen's order for a 3-vector.
TROCAR_AVX2_EXACT __m256d dot(const V3& a, const V3& b) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a.x, b.x), _mm256_mul_pd(a.y, b.y)), _mm256_mul_pd(a.z, b.z));
}
TROCAR_AVX2_EXACT V3 cross(const V3& a, const V3& b) {
  return {_mm256_sub_pd(_mm256_mul_pd(a.y, b.z), _mm256_mul_pd(a.z, b.y)),
          _mm256_sub_pd(_mm256_mul_pd(a.z, b.x), _mm256_mul_pd(a.x, b.z)),
          _mm256_sub_pd(_mm256_mul_pd(a.x, b.y), _mm256_mul_pd(a.y, b.x))};
}
// mask ? b : a, per lane.
TROCAR_AVX2_EXACT V3 select(const V3& a, const V3& b, __m256d mask) {
  return {_mm256_blendv_pd(a.x, b.x, mask), _mm256_blendv_pd(a.y, b.y, mask), _mm256_blendv_pd(a.z, b.z, mask)};
}
TROCAR_AVX2_EXACT __m256d lt(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
TROCAR_AVX2_EXACT __m256d le(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
TROCAR_AVX2_EXACT __m256d both(__m256d a, __m256d b) { return _mm256_and_pd(a, b); }
TROCAR_AVX2_EXACT __m256d either(__m256d a, __m256d b) { return _mm256_or_pd(a, b); }
TROCAR_AVX2_EXACT __m256d absolute(__m256d a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }

// Four points as x, y, z vectors (masked loads, 4 × 4 transpose; nothing past a point is read).
TROCAR_AVX2_EXACT V3 load4(const Vec3* p0, const Vec3* p1, const Vec3* p2, const Vec3* p3) {
  const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
  const __m256d r0 = _mm256_maskload_pd(p0->data(), xyz);
  const __m256d r1 = _mm256_maskload_pd(p1->data(), xyz);
  const __m256d r2 = _mm256_maskload_pd(p2->data(), xyz);
  const __m256d r3 = _mm256_maskload_pd(p3->data(), xyz);
  const __m256d xz01 = _mm256_unpacklo_pd(r0, r1);
  const __m256d y01 = _mm256_unpackhi_pd(r0, r1);
  const __m256d xz23 = _mm256_unpacklo_pd(r2, r3);
  const __m256d y23 = _mm256_unpackhi_pd(r2, r3);
  return {_mm256_permute2f128_pd(xz01, xz23, 0x20), _mm256_permute2f128_pd(y01, y23, 0x20),
          _mm256_permute2f128_pd(xz01, xz23, 0x31)};
}

// The three distances all > eps or all < −eps (strictly_one_side() in the scalar code).
TROCAR_AVX2_EXACT __m256d one_side(const __m256d (&d)[3], __m256d eps, __m256d neg_eps) {
  return either(both(both(lt(eps, d[0]), lt(eps, d[1])), lt(eps, d[2])),
                both(both(lt(d[0], neg_eps), lt(d[1], neg_eps)), lt(d[2], neg_eps)));
}

// make_primitive() of triangle q0q1q2 for a proper triangle: the unit normal by Gram–Schmidt on
// the longest edge. `proper` is the lanes where the scalar code takes that branch with a
// non-zero normal.
struct Prim4 {
  V3 n;
  __m256d proper;
};
TROCAR_AVX2_EXACT Prim4 prim4(const V3& q0, const V3& q1, const V3& q2) {
  const V3 e0 = sub(q1, q0);  // edge k = q_k → q_k+1
  const V3 e1 = sub(q2, q1);
  const V3 e2 = sub(q0, q2);
  const __m256d len0 = dot(e0, e0);
  const __m256d len1 = dot(e1, e1);
  const __m256d len2 = dot(e2, e2);
  // std::max_element: the first largest.
  const __m256d is1 = lt(len0, len1);
  const __m256d len01 = _mm256_blendv_pd(len0, len1, is1);
  const __m256d is2 = lt(len01, len2);
  const __m256d longest = _mm256_blendv_pd(len01, len2, is2);
  const V3 area = cross(e0, sub(q2, q0));
  const __m256d area2_sq = dot(area, area);
  const __m256d zero = _mm256_setzero_pd();
  constexpr double kRatio2 = kDegenerateRatio * kDegenerateRatio;
  const __m256d proper = both(lt(zero, longest), lt(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(kRatio2), longest), longest), area2_sq));
  // e = the longest edge (from vertex l), f = the vector from vertex l to the third one.
  const V3 e = select(select(e0, e1, is1), e2, is2);
  const V3 f = select(select(sub(q2, q0), sub(q0, q1), is1), sub(q1, q2), is2);
  const __m256d s = _mm256_div_pd(dot(f, e), longest);
  const V3 g = sub(f, scale(s, e));
  const V3 n = cross(e, g);
  const __m256d n_len = _mm256_sqrt_pd(dot(n, n));
  return {divide(n, n_len), both(proper, lt(zero, n_len))};
}

// trace() for a triangle with no snapped distance zero and mixed signs: the two crossing edges,
// in edge order (edges 0 and 2 when vertex 0 is the lone one, 0 and 1 for vertex 1, 1 and 2 for
// vertex 2).
struct Trace4 {
  V3 p0, p1;
};
TROCAR_AVX2_EXACT V3 crossing(const V3& vi, const V3& vj, __m256d di, __m256d dj) {
  return add(vi, scale(_mm256_div_pd(di, _mm256_sub_pd(di, dj)), sub(vj, vi)));
}
TROCAR_AVX2_EXACT Trace4 trace4(const V3& v0, const V3& v1, const V3& v2, __m256d d0, __m256d d1, __m256d d2) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d pos0 = lt(zero, d0);
  const __m256d pos1 = lt(zero, d1);
  const __m256d pos2 = lt(zero, d2);
  const __m256d edge0 = _mm256_xor_pd(pos0, pos1);  // signs differ (none is zero here)
  const __m256d edge2 = _mm256_xor_pd(pos2, pos0);
  const V3 c0 = crossing(v0, v1, d0, d1);
  const V3 c1 = crossing(v1, v2, d1, d2);
  const V3 c2 = crossing(v2, v0, d2, d0);
  return {select(c1, c0, edge0), select(c1, c2, edge2)};
}

}  // namespace

__attribute__((target("avx2"))) int exact4_avx2(const Vec3* const (&c)[4][6], TriTriResult (&r)[4]) {
  const V3 o = load4(c[0][0], c[1][0], c[2][0], c[3][0]);
  const __m256d zero = _mm256_setzero_pd();
  const V3 v0 = {zero, zero, zero};  // a0 − a0 is taken as exactly zero, as in the scalar code
  const V3 v1 = sub(load4(c[0][1], c[1][1], c[2][1], c[3][1]), o);
  const V3 v2 = sub(load4(c[0][2], c[1][2], c[2][2], c[3][2]), o);
  const V3 v3 = sub(load4(c[0][3], c[1][3], c[2][3], c[3][3]), o);
  const V3 v4 = sub(load4(c[0][4], c[1][4], c[2][4], c[3][4]), o);
  const V3 v5 = sub(load4(c[0][5], c[1][5], c[2][5], c[3][5]), o);
  // Finite (the scalar code returns early otherwise: left to it) and the pair's size L.
  const __m256d inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  __m256d finite = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  __m256d lo_x = zero, lo_y = zero, lo_z = zero, hi_x = zero, hi_y = zero, hi_z = zero;
  for (const V3* v : {&v1, &v2, &v3, &v4, &v5}) {
    finite = both(finite, both(both(lt(absolute(v->x), inf), lt(absolute(v->y), inf)), lt(absolute(v->z), inf)));
    lo_x = _mm256_min_pd(lo_x, v->x);
    lo_y = _mm256_min_pd(lo_y, v->y);
    lo_z = _mm256_min_pd(lo_z, v->z);
    hi_x = _mm256_max_pd(hi_x, v->x);
    hi_y = _mm256_max_pd(hi_y, v->y);
    hi_z = _mm256_max_pd(hi_z, v->z);
  }
  const __m256d size = _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(hi_x, lo_x), _mm256_sub_pd(hi_y, lo_y)),
                                     _mm256_sub_pd(hi_z, lo_z));
  const __m256d eps = _mm256_mul_pd(_mm256_set1_pd(kTriTriTolerance), size);
  const __m256d neg_eps = _mm256_sub_pd(zero, eps);  // −eps (the sign of a zero is moot here)

  const Prim4 a = prim4(v0, v1, v2);
  const Prim4 b = prim4(v3, v4, v5);
  __m256d handled = both(finite, both(a.proper, b.proper));
  if (_mm256_movemask_pd(handled) == 0) return 0;

  // Distances to the other plane (a.v[0] is the origin), snapped to zero within eps.
  const __m256d db[3] = {dot(a.n, v3), dot(a.n, v4), dot(a.n, v5)};
  const __m256d da[3] = {dot(b.n, sub(v0, v3)), dot(b.n, sub(v1, v3)), dot(b.n, sub(v2, v3))};
  // All of one triangle strictly beyond ±eps of the other's plane: no intersection.
  const __m256d apart = either(one_side(db, eps, neg_eps), one_side(da, eps, neg_eps));
  // A vertex within eps of the other plane (snapped to zero: a trace through a vertex, or
  // coplanar triangles): left to the scalar code unless the pair is apart anyway.
  __m256d on_plane = zero;
  for (int k = 0; k < 3; ++k) on_plane = either(on_plane, either(le(absolute(db[k]), eps), le(absolute(da[k]), eps)));
  handled = _mm256_andnot_pd(_mm256_andnot_pd(apart, on_plane), handled);

  const Trace4 ta = trace4(v0, v1, v2, da[0], da[1], da[2]);
  const Trace4 tb = trace4(v3, v4, v5, db[0], db[1], db[2]);
  const __m256d len_a = _mm256_sqrt_pd(dot(sub(ta.p1, ta.p0), sub(ta.p1, ta.p0)));
  const __m256d len_b = _mm256_sqrt_pd(dot(sub(tb.p1, tb.p0), sub(tb.p1, tb.p0)));
  const V3 line = cross(a.n, b.n);
  const __m256d line_len = _mm256_sqrt_pd(dot(line, line));
  const __m256d longest = _mm256_blendv_pd(len_a, len_b, lt(len_a, len_b));  // std::max
  // The ordering direction: nA × nB where it is the better conditioned, else the longer trace's
  // own direction (a's on a tie); two single-point traces are left to the scalar code.
  const __m256d by_line = both(lt(zero, line_len), le(longest, _mm256_mul_pd(line_len, size)));
  handled = both(handled, either(apart, either(by_line, lt(zero, longest))));
  const int lanes = _mm256_movemask_pd(handled);
  if (lanes == 0) return 0;

  V3 u = divide(line, line_len);
  if (_mm256_movemask_pd(_mm256_andnot_pd(either(apart, by_line), handled)) != 0) {
    const V3 along_a = divide(sub(ta.p1, ta.p0), len_a);
    const V3 along_b = divide(sub(tb.p1, tb.p0), len_b);
    u = select(select(along_b, along_a, le(len_b, len_a)), u, by_line);
  }
  __m256d t_a0 = dot(u, ta.p0), t_a1 = dot(u, ta.p1), t_b0 = dot(u, tb.p0), t_b1 = dot(u, tb.p1);
  const __m256d swap_a = lt(t_a1, t_a0);
  const __m256d swap_b = lt(t_b1, t_b0);
  const V3 pa0 = select(ta.p0, ta.p1, swap_a);
  const V3 pa1 = select(ta.p1, ta.p0, swap_a);
  const V3 pb0 = select(tb.p0, tb.p1, swap_b);
  const V3 pb1 = select(tb.p1, tb.p0, swap_b);
  const __m256d sa0 = _mm256_blendv_pd(t_a0, t_a1, swap_a);
  const __m256d sa1 = _mm256_blendv_pd(t_a1, t_a0, swap_a);
  const __m256d sb0 = _mm256_blendv_pd(t_b0, t_b1, swap_b);
  const __m256d sb1 = _mm256_blendv_pd(t_b1, t_b0, swap_b);
  // lo = max(ta0, tb0), hi = min(ta1, tb1) (only compared, so the sign of a zero is moot).
  const __m256d lo = _mm256_max_pd(sa0, sb0);
  const __m256d hi = _mm256_min_pd(sa1, sb1);
  const V3 p_lo = select(pb0, pa0, le(sb0, sa0));  // ta0 >= tb0 ? pa0 : pb0
  const V3 p_hi = select(pb1, pa1, le(sa1, sb1));  // ta1 <= tb1 ? pa1 : pb1
  const __m256d miss = either(apart, lt(_mm256_add_pd(hi, eps), lo));
  const __m256d touch = lt(hi, lo);  // within the tolerance: the midpoint, P = Q
  const V3 mid = scale(_mm256_set1_pd(0.5), add(p_lo, p_hi));
  const V3 p = add(select(p_lo, mid, touch), o);
  const V3 q = add(select(p_hi, mid, touch), o);
  alignas(32) double px[4], py[4], pz[4], qx[4], qy[4], qz[4];
  _mm256_store_pd(px, p.x);
  _mm256_store_pd(py, p.y);
  _mm256_store_pd(pz, p.z);
  _mm256_store_pd(qx, q.x);
  _mm256_store_pd(qy, q.y);
  _mm256_store_pd(qz, q.z);
  const int misses = _mm256_movemask_pd(miss);
  for (int k = 0; k < 4; ++k) {
    if (!(lanes >> k & 1)) continue;
    if (misses >> k & 1) {
      r[k] = TriTriResult{};
    } else {
      r[k] = {true, false, Vec3(px[k], py[k], pz[k]), Vec3(qx[k], qy[k], qz[k])};
    }
  }
  return lanes;
}

#else

int exact4_avx2(const Vec3* const (&)[4][6], TriTriResult (&)[4]) { return 0; }

#endif

}  // namespace trocar::narrow_detail
