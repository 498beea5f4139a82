#pragma once
/// Internal to the narrow phase: intersect_triangles (geometry/triangle_triangle.cpp) on S::kLanes
/// pairs at once, bit for bit, for the common case: both triangles proper, finite, crossing each
/// other's plane with no vertex within the tolerance of the other plane. Every other lane
/// (coplanar, degenerate, a vertex on the other plane, two single-point traces, non-finite input)
/// is left to the scalar function. Each lane runs the scalar code's operations in the scalar
/// code's order (Eigen's dot and squaredNorm sum x, y, then z; cross products by the textbook
/// formula; divisions, not reciprocals), and the including file is compiled without contraction
/// (no FMA may be formed): IEEE arithmetic is then the same in a lane as in a scalar register.
/// Branches become blends (all sides are computed; the unused ones may be inf or NaN and are
/// dropped). S is the vector width's table (narrow_phase_lanes_avx2.h), and this
/// header is included after its target pragma, so everything here is compiled for it;
/// exact_batch_test.cpp checks the results against intersect_triangles bit for bit.
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/geometry/tolerance.h"

namespace trocar::narrow_detail {
namespace {

template <class S>
struct Exact {
  using V = typename S::V;
  using M = typename S::M;

  struct V3 {
    V x, y, z;
  };

  static V3 sub(const V3& a, const V3& b) { return {S::sub(a.x, b.x), S::sub(a.y, b.y), S::sub(a.z, b.z)}; }
  static V3 add(const V3& a, const V3& b) { return {S::add(a.x, b.x), S::add(a.y, b.y), S::add(a.z, b.z)}; }
  static V3 scale(V s, const V3& a) { return {S::mul(s, a.x), S::mul(s, a.y), S::mul(s, a.z)}; }
  static V3 divide(const V3& a, V s) { return {S::div(a.x, s), S::div(a.y, s), S::div(a.z, s)}; }
  // (x·x + y·y) + z·z, Eigen's order for a 3-vector.
  static V dot(const V3& a, const V3& b) {
    return S::add(S::add(S::mul(a.x, b.x), S::mul(a.y, b.y)), S::mul(a.z, b.z));
  }
  static V3 cross(const V3& a, const V3& b) {
    return {S::sub(S::mul(a.y, b.z), S::mul(a.z, b.y)), S::sub(S::mul(a.z, b.x), S::mul(a.x, b.z)),
            S::sub(S::mul(a.x, b.y), S::mul(a.y, b.x))};
  }
  // mask ? b : a, per lane.
  static V3 select(const V3& a, const V3& b, M mask) {
    return {S::blend(a.x, b.x, mask), S::blend(a.y, b.y, mask), S::blend(a.z, b.z, mask)};
  }

  // The three distances all > eps or all < −eps (strictly_one_side() in the scalar code).
  static M one_side(const V (&d)[3], V eps, V neg_eps) {
    return S::or_(S::and_(S::and_(S::lt(eps, d[0]), S::lt(eps, d[1])), S::lt(eps, d[2])),
                  S::and_(S::and_(S::lt(d[0], neg_eps), S::lt(d[1], neg_eps)), S::lt(d[2], neg_eps)));
  }

  // make_primitive() of triangle q0q1q2 for a proper triangle: the unit normal by Gram–Schmidt
  // on the longest edge. `proper`: the lanes where the scalar code takes that branch with a
  // non-zero normal.
  struct Prim {
    V3 n;
    M proper;
  };
  static Prim prim(const V3& q0, const V3& q1, const V3& q2) {
    const V3 e0 = sub(q1, q0);  // edge k = q_k → q_k+1
    const V3 e1 = sub(q2, q1);
    const V3 e2 = sub(q0, q2);
    const V len0 = dot(e0, e0);
    const V len1 = dot(e1, e1);
    const V len2 = dot(e2, e2);
    // std::max_element: the first largest.
    const M is1 = S::lt(len0, len1);
    const V len01 = S::blend(len0, len1, is1);
    const M is2 = S::lt(len01, len2);
    const V longest = S::blend(len01, len2, is2);
    const V3 area = cross(e0, sub(q2, q0));
    const V area2_sq = dot(area, area);
    const V zero = S::zero();
    constexpr double kRatio2 = kDegenerateRatio * kDegenerateRatio;
    const M proper = S::and_(S::lt(zero, longest), S::lt(S::mul(S::mul(S::set1(kRatio2), longest), longest), area2_sq));
    // e = the longest edge (from vertex l), f = the vector from vertex l to the third one.
    const V3 e = select(select(e0, e1, is1), e2, is2);
    const V3 f = select(select(sub(q2, q0), sub(q0, q1), is1), sub(q1, q2), is2);
    const V s = S::div(dot(f, e), longest);
    const V3 g = sub(f, scale(s, e));
    const V3 n = cross(e, g);
    const V n_len = S::sqrt(dot(n, n));
    return {divide(n, n_len), S::and_(proper, S::lt(zero, n_len))};
  }

  // trace() for a triangle with no snapped distance zero and mixed signs: the two crossing
  // edges, in edge order (edges 0 and 2 when vertex 0 is the lone one, 0 and 1 for vertex 1, 1
  // and 2 for vertex 2).
  struct Trace {
    V3 p0, p1;
  };
  static V3 crossing(const V3& vi, const V3& vj, V di, V dj) {
    return add(vi, scale(S::div(di, S::sub(di, dj)), sub(vj, vi)));
  }
  static Trace trace(const V3& v0, const V3& v1, const V3& v2, V d0, V d1, V d2) {
    const V zero = S::zero();
    const M pos0 = S::lt(zero, d0);
    const M pos1 = S::lt(zero, d1);
    const M pos2 = S::lt(zero, d2);
    const M edge0 = S::xor_(pos0, pos1);  // signs differ (none is zero here)
    const M edge2 = S::xor_(pos2, pos0);
    const V3 c0 = crossing(v0, v1, d0, d1);
    const V3 c1 = crossing(v1, v2, d1, d2);
    const V3 c2 = crossing(v2, v0, d2, d0);
    return {select(c1, c0, edge0), select(c1, c2, edge2)};
  }

  // Corner k (a0, a1, a2, b0, b1, b2) of every pair.
  static V3 corner(const Vec3* const (*c)[6], int k) {
    const double* q[S::kLanes];
    for (int l = 0; l < S::kLanes; ++l) q[l] = c[l][k]->data();
    V3 v;
    S::load(q, v.x, v.y, v.z);
    return v;
  }

  // c[k]: a0, a1, a2, b0, b1, b2 of pair k; returns the mask of the lanes answered in r.
  static unsigned run(const Vec3* const (*c)[6], TriTriResult* r) {
    const V3 o = corner(c, 0);
    const V zero = S::zero();
    const V3 v0 = {zero, zero, zero};  // a0 − a0 is taken as exactly zero, as in the scalar code
    const V3 v1 = sub(corner(c, 1), o);
    const V3 v2 = sub(corner(c, 2), o);
    const V3 v3 = sub(corner(c, 3), o);
    const V3 v4 = sub(corner(c, 4), o);
    const V3 v5 = sub(corner(c, 5), o);
    // Finite (the scalar code returns early otherwise: left to it) and the pair's size L.
    const V inf = S::set1(std::numeric_limits<double>::infinity());
    M finite = S::lt(zero, inf);  // all lanes
    V lo_x = zero, lo_y = zero, lo_z = zero, hi_x = zero, hi_y = zero, hi_z = zero;
    for (const V3* v : {&v1, &v2, &v3, &v4, &v5}) {
      finite = S::and_(finite, S::and_(S::and_(S::lt(S::abs(v->x), inf), S::lt(S::abs(v->y), inf)),
                                       S::lt(S::abs(v->z), inf)));
      lo_x = S::min(lo_x, v->x);
      lo_y = S::min(lo_y, v->y);
      lo_z = S::min(lo_z, v->z);
      hi_x = S::max(hi_x, v->x);
      hi_y = S::max(hi_y, v->y);
      hi_z = S::max(hi_z, v->z);
    }
    const V size = S::max(S::max(S::sub(hi_x, lo_x), S::sub(hi_y, lo_y)), S::sub(hi_z, lo_z));
    const V eps = S::mul(S::set1(kTriTriTolerance), size);
    const V neg_eps = S::sub(zero, eps);  // −eps (the sign of a zero is moot here)

    const Prim a = prim(v0, v1, v2);
    const Prim b = prim(v3, v4, v5);
    M handled = S::and_(finite, S::and_(a.proper, b.proper));
    if (S::bits(handled) == 0) return 0;

    // Distances to the other plane (a.v[0] is the origin), snapped to zero within eps.
    const V db[3] = {dot(a.n, v3), dot(a.n, v4), dot(a.n, v5)};
    const V da[3] = {dot(b.n, sub(v0, v3)), dot(b.n, sub(v1, v3)), dot(b.n, sub(v2, v3))};
    // All of one triangle strictly beyond ±eps of the other's plane: no intersection.
    const M apart = S::or_(one_side(db, eps, neg_eps), one_side(da, eps, neg_eps));
    // A vertex within eps of the other plane (snapped to zero: a trace through a vertex, or
    // coplanar triangles): left to the scalar code unless the pair is apart anyway.
    M on_plane = S::lt(inf, zero);  // no lane
    for (int k = 0; k < 3; ++k) {
      on_plane = S::or_(on_plane, S::or_(S::le(S::abs(db[k]), eps), S::le(S::abs(da[k]), eps)));
    }
    handled = S::andnot(S::andnot(apart, on_plane), handled);

    const Trace ta = trace(v0, v1, v2, da[0], da[1], da[2]);
    const Trace tb = trace(v3, v4, v5, db[0], db[1], db[2]);
    const V len_a = S::sqrt(dot(sub(ta.p1, ta.p0), sub(ta.p1, ta.p0)));
    const V len_b = S::sqrt(dot(sub(tb.p1, tb.p0), sub(tb.p1, tb.p0)));
    const V3 line = cross(a.n, b.n);
    const V line_len = S::sqrt(dot(line, line));
    const V longest = S::blend(len_a, len_b, S::lt(len_a, len_b));  // std::max
    // The ordering direction: nA × nB where it is the better conditioned, else the longer
    // trace's own direction (a's on a tie); two single-point traces are left to the scalar code.
    const M by_line = S::and_(S::lt(zero, line_len), S::le(longest, S::mul(line_len, size)));
    handled = S::and_(handled, S::or_(apart, S::or_(by_line, S::lt(zero, longest))));
    const unsigned lanes = S::bits(handled);
    if (lanes == 0) return 0;

    V3 u = divide(line, line_len);
    if (S::bits(S::andnot(S::or_(apart, by_line), handled)) != 0) {
      const V3 along_a = divide(sub(ta.p1, ta.p0), len_a);
      const V3 along_b = divide(sub(tb.p1, tb.p0), len_b);
      u = select(select(along_b, along_a, S::le(len_b, len_a)), u, by_line);
    }
    const V t_a0 = dot(u, ta.p0), t_a1 = dot(u, ta.p1), t_b0 = dot(u, tb.p0), t_b1 = dot(u, tb.p1);
    const M swap_a = S::lt(t_a1, t_a0);
    const M swap_b = S::lt(t_b1, t_b0);
    const V3 pa0 = select(ta.p0, ta.p1, swap_a);
    const V3 pa1 = select(ta.p1, ta.p0, swap_a);
    const V3 pb0 = select(tb.p0, tb.p1, swap_b);
    const V3 pb1 = select(tb.p1, tb.p0, swap_b);
    const V sa0 = S::blend(t_a0, t_a1, swap_a);
    const V sa1 = S::blend(t_a1, t_a0, swap_a);
    const V sb0 = S::blend(t_b0, t_b1, swap_b);
    const V sb1 = S::blend(t_b1, t_b0, swap_b);
    // lo = max(ta0, tb0), hi = min(ta1, tb1) (only compared, so the sign of a zero is moot).
    const V lo = S::max(sa0, sb0);
    const V hi = S::min(sa1, sb1);
    const V3 p_lo = select(pb0, pa0, S::le(sb0, sa0));  // ta0 >= tb0 ? pa0 : pb0
    const V3 p_hi = select(pb1, pa1, S::le(sa1, sb1));  // ta1 <= tb1 ? pa1 : pb1
    const M miss = S::or_(apart, S::lt(S::add(hi, eps), lo));
    const M touch = S::lt(hi, lo);  // within the tolerance: the midpoint, P = Q
    const V3 mid = scale(S::set1(0.5), add(p_lo, p_hi));
    const V3 p = add(select(p_lo, mid, touch), o);
    const V3 q = add(select(p_hi, mid, touch), o);
    alignas(64) double px[S::kLanes], py[S::kLanes], pz[S::kLanes], qx[S::kLanes], qy[S::kLanes], qz[S::kLanes];
    S::store(px, p.x);
    S::store(py, p.y);
    S::store(pz, p.z);
    S::store(qx, q.x);
    S::store(qy, q.y);
    S::store(qz, q.z);
    const unsigned misses = S::bits(miss);
    for (int k = 0; k < S::kLanes; ++k) {
      if (!(lanes >> k & 1)) continue;
      if (misses >> k & 1) {
        r[k] = TriTriResult{};
      } else {
        r[k] = {true, false, Vec3(px[k], py[k], pz[k]), Vec3(qx[k], qy[k], qz[k])};
      }
    }
    return lanes;
  }
};

}  // namespace
}  // namespace trocar::narrow_detail
