#pragma once
// The narrow phase's rejection tests on kLanes candidates at once, written over a vector width
// (internal; included only by narrow_phase_avx2.cpp inside its target region). Lane k holds
// candidate k: the tests of the portable path (narrow_phase.cpp) run on every lane — A's plane
// against B's corners, B's plane against A's corners (each with the conservative 1e-9·L
// margin), then the interval test on the line nA × nB (Möller, "A Fast Triangle-Triangle Intersection Test", JGT 1997, made conservative as
// there). FMA and one reciprocal per edge round differently from the portable path by a few ulp,
// which the margins (orders of magnitude wider) absorb: both paths reject only pairs the exact
// test rejects, so the contacts are the same.
//
// S supplies, for its vector V of kLanes doubles and its lane mask M: set1, zero, add, sub, mul,
// div, sqrt, min, max, abs, fmadd (a·b + c), fmsub (a·b − c), gt, ge, le (ordered compares),
// and_, or_, andnot (¬a ∧ b), blend (m ? b : a), bits (lane k → bit k), and load(q, x, y, z):
// the kLanes points q as x, y, z vectors (reading three doubles from each).
#include <limits>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/narrow_phase_detail.h"

namespace trocar::narrow_detail {

template <class S>
struct Reject {
  using V = typename S::V;
  using M = typename S::M;
  struct V3 {
    V x, y, z;
  };

  static V3 sub(const V3& a, const V3& b) { return {S::sub(a.x, b.x), S::sub(a.y, b.y), S::sub(a.z, b.z)}; }
  static V dot(const V3& a, const V3& b) { return S::fmadd(a.x, b.x, S::fmadd(a.y, b.y, S::mul(a.z, b.z))); }
  static V3 cross(const V3& a, const V3& b) {
    return {S::fmsub(a.y, b.z, S::mul(a.z, b.y)), S::fmsub(a.z, b.x, S::mul(a.x, b.z)),
            S::fmsub(a.x, b.y, S::mul(a.y, b.x))};
  }

  // The plane of a triangle with edges e1, e2 (and e2 − e1): normal, |n|², well-shaped mask.
  struct Plane {
    V3 n;
    V n2;
    M well;
  };
  static Plane plane(const V3& e1, const V3& e2) {
    Plane p;
    p.n = cross(e1, e2);
    p.n2 = dot(p.n, p.n);
    const V3 e3 = sub(e2, e1);
    const V longest2 = S::max(S::max(dot(e1, e1), dot(e2, e2)), dot(e3, e3));
    p.well = S::gt(p.n2, S::mul(S::set1(1e-6), S::mul(longest2, longest2)));
    return p;
  }

  // Mask of the lanes whose three distances d (× |n|) lie strictly on one side of a well-shaped
  // plane by more than 1e-9·L: d_i² > 1e-18·L²·|n|² (as separated_by_plane in narrow_phase.cpp).
  static M separated(const Plane& p, V d0, V d1, V d2, V size2) {
    const V zero = S::zero();
    const M above = S::and_(S::and_(S::gt(d0, zero), S::gt(d1, zero)), S::gt(d2, zero));
    const M below = S::and_(S::and_(S::gt(zero, d0), S::gt(zero, d1)), S::gt(zero, d2));
    const V threshold2 = S::mul(S::mul(S::set1(1e-18), size2), p.n2);
    const M far = S::and_(S::and_(S::gt(S::mul(d0, d0), threshold2), S::gt(S::mul(d1, d1), threshold2)),
                          S::gt(S::mul(d2, d2), threshold2));
    return S::and_(S::and_(p.well, S::or_(above, below)), far);
  }

  // The projections on the line of the parts of a triangle within the slab |d| ≤ tau of the
  // other plane, edge by edge (as slab_interval in narrow_phase.cpp): [lo, hi] per lane.
  struct Interval {
    V lo;  // +inf when empty
    V hi;  // −inf when empty

    // (A function rather than member initialisers: an implicit constructor would be compiled
    // outside the caller's target region.)
    void clear() {
      lo = S::set1(std::numeric_limits<double>::infinity());
      hi = S::set1(-std::numeric_limits<double>::infinity());
    }

    // Edge from corner i (projection pi, distance di) to corner j.
    void edge(V pi, V pj, V di, V dj, V tau) {
      const V neg_tau = S::sub(S::zero(), tau);
      const M outside =
          S::or_(S::and_(S::gt(di, tau), S::gt(dj, tau)), S::and_(S::gt(neg_tau, di), S::gt(neg_tau, dj)));
      const V dd = S::sub(dj, di);
      const M steep = S::gt(S::abs(dd), tau);
      // d(λ) = di + λ·dd ∈ [−tau, tau] for λ between a and b (only where the edge is steep).
      // One division for both (a reciprocal rounds differently from the portable path's two
      // divisions, by a few ulp: nothing next to the slab's 1e-9·L).
      const V inv = S::div(S::set1(1.0), dd);
      const V a = S::mul(S::sub(neg_tau, di), inv);
      const V b = S::mul(S::sub(tau, di), inv);
      const V zero = S::zero();
      const V one = S::set1(1.0);
      V l0 = S::blend(zero, S::max(zero, S::min(a, b)), steep);
      V l1 = S::blend(one, S::min(one, S::max(a, b)), steep);
      // l0 > l1 only by rounding (the edge just reaches the slab): keep the middle, in [0, 1].
      const M crossed = S::gt(l0, l1);
      const V mid = S::min(one, S::max(zero, S::mul(S::set1(0.5), S::add(l0, l1))));
      l0 = S::blend(l0, mid, crossed);
      l1 = S::blend(l1, mid, crossed);
      const V span = S::sub(pj, pi);
      const V x0 = S::fmadd(l0, span, pi);
      const V x1 = S::fmadd(l1, span, pi);
      lo = S::blend(S::min(lo, S::min(x0, x1)), lo, outside);
      hi = S::blend(S::max(hi, S::max(x0, x1)), hi, outside);
    }
  };

  /// Bit k set: candidate k survives every test (it may intersect).
  static unsigned run(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs) {
    const Vec3* pa = oa.positions.data();
    const Vec3* pb = ob.positions.data();
    const Triangle* ta[S::kLanes];
    const Triangle* tb[S::kLanes];
    for (int k = 0; k < S::kLanes; ++k) {
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
    const V zero = S::zero();
    V lo_x = zero, lo_y = zero, lo_z = zero, hi_x = zero, hi_y = zero, hi_z = zero;
    for (const V3* c : {&ra1, &ra2, &rb0, &rb1, &rb2}) {
      lo_x = S::min(lo_x, c->x);
      lo_y = S::min(lo_y, c->y);
      lo_z = S::min(lo_z, c->z);
      hi_x = S::max(hi_x, c->x);
      hi_y = S::max(hi_y, c->y);
      hi_z = S::max(hi_z, c->z);
    }
    const V size = S::max(S::max(S::sub(hi_x, lo_x), S::sub(hi_y, lo_y)), S::sub(hi_z, lo_z));
    const M finite = S::gt(S::set1(std::numeric_limits<double>::infinity()), size);
    const V size2 = S::mul(size, size);

    const Plane plane_a = plane(ra1, ra2);
    const V db0 = dot(plane_a.n, rb0);
    const V db1 = dot(plane_a.n, rb1);
    const V db2 = dot(plane_a.n, rb2);
    const M sep_a = separated(plane_a, db0, db1, db2, size2);
    const Plane plane_b = plane(sub(rb1, rb0), sub(rb2, rb0));
    const V da0 = S::sub(zero, dot(plane_b.n, rb0));
    const V da1 = dot(plane_b.n, sub(ra1, rb0));
    const V da2 = dot(plane_b.n, sub(ra2, rb0));
    const M sep_b = separated(plane_b, da0, da1, da2, size2);
    const M planes_keep = S::andnot(S::or_(sep_a, sep_b), finite);
    if (S::bits(planes_keep) == 0) return 0;

    // The interval test on the lanes the planes kept (as separated_on_line in narrow_phase.cpp).
    const V3 dir = cross(plane_a.n, plane_b.n);
    const V dir2 = dot(dir, dir);
    const M line_ok = S::and_(S::and_(plane_a.well, plane_b.well),
                              S::ge(dir2, S::mul(S::set1(1e-4), S::mul(plane_a.n2, plane_b.n2))));
    const V eps_size = S::mul(S::set1(1e-9), size);
    Interval ia;
    ia.clear();
    const V tau_a = S::mul(eps_size, S::sqrt(plane_b.n2));
    const V pa1 = dot(dir, ra1);
    const V pa2 = dot(dir, ra2);
    ia.edge(zero, pa1, da0, da1, tau_a);
    ia.edge(pa1, pa2, da1, da2, tau_a);
    ia.edge(pa2, zero, da2, da0, tau_a);
    Interval ib;
    ib.clear();
    const V tau_b = S::mul(eps_size, S::sqrt(plane_a.n2));
    const V pb0 = dot(dir, rb0);
    const V pb1 = dot(dir, rb1);
    const V pb2 = dot(dir, rb2);
    ib.edge(pb0, pb1, db0, db1, tau_b);
    ib.edge(pb1, pb2, db1, db2, tau_b);
    ib.edge(pb2, pb0, db2, db0, tau_b);
    const M nonempty = S::and_(S::le(ia.lo, ia.hi), S::le(ib.lo, ib.hi));
    const V gap = S::sub(S::max(ia.lo, ib.lo), S::min(ia.hi, ib.hi));
    const M apart = S::and_(S::gt(gap, zero), S::gt(S::mul(gap, gap), S::mul(S::mul(S::set1(1e-14), size2), dir2)));
    const M sep_line = S::and_(S::and_(line_ok, nonempty), apart);
    return S::bits(S::andnot(sep_line, planes_keep));
  }

  static V3 corner(const Vec3* p, const Triangle* const (&t)[S::kLanes], int c) {
    const double* q[S::kLanes];
    for (int k = 0; k < S::kLanes; ++k) q[k] = p[(*t[k])[c]].data();
    V3 r;
    S::load(q, r.x, r.y, r.z);
    return r;
  }
};

}  // namespace trocar::narrow_detail
