#include "trocar/geometry/triangle_triangle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "trocar/geometry/closest_point.h"
#include "trocar/geometry/tolerance.h"

namespace trocar {
namespace {

// A triangle reduced to what it is geometrically: a proper triangle with its unit normal and
// unit inward edge normals, or (degenerate) the segment s0s1 spanned by its longest edge.
struct Primitive {
  bool is_triangle = false;
  // Vertices (proper triangle): the caller's three consecutive points, not a copy (copying
  // 24-byte vectors and reading them back in 16-byte halves stalled store forwarding).
  const Vec3* v = nullptr;
  Vec3 n;                   // unit normal (b−a)×(c−a)/|…|
  std::array<Real, 3> len2;  // squared edge lengths, edge k = v_k → v_k+1
  // m[k]: unit in-plane normal of edge k, pointing into the triangle. Only the in-plane tests
  // (coplanar, segment–triangle) need them, so with_edge_normals() fills them on demand.
  std::array<Vec3, 3> m;
  Real area2_sq = 0;        // |(b−a)×(c−a)|² = (twice the area)²
  Vec3 s0, s1;              // segment (degenerate)
};

Primitive make_primitive(const Vec3* v) {
  Primitive t;
  std::array<Real, 3> len2{};
  for (int k = 0; k < 3; ++k) len2[k] = (v[(k + 1) % 3] - v[k]).squaredNorm();
  const int longest = static_cast<int>(std::max_element(len2.begin(), len2.end()) - len2.begin());
  const Vec3 cross = (v[1] - v[0]).cross(v[2] - v[0]);
  const Real area2_sq = cross.squaredNorm();  // (twice the area)²
  if (len2[longest] > 0 &&
      area2_sq > kDegenerateRatio * kDegenerateRatio * len2[longest] * len2[longest]) {
    t.is_triangle = true;
    t.v = v;
    // Unit normal by Gram–Schmidt on the longest edge e (from vertex l) and the vector f to the
    // third vertex: n ∝ e × (f − (f·e/e·e)·e). For a sliver of height h the plain cross product
    // has a direction error ~ε·L/h that tilts the plane off its own vertices by ~ε·L²/h; here
    // the error only rotates the plane about e, which moves the vertices by ~ε·L. (l, l+1, l+2)
    // is a cyclic relabelling, so n has the orientation of (b−a)×(c−a).
    const Vec3& o = v[longest];
    const Vec3 e = v[(longest + 1) % 3] - o;
    const Vec3 f = v[(longest + 2) % 3] - o;
    const Vec3 n = e.cross(f - (f.dot(e) / len2[longest]) * e);
    const Real n_len = n.norm();
    t.n = n_len > 0 ? Vec3(n / n_len) : Vec3(cross.normalized());
    t.area2_sq = area2_sq;
    t.len2 = len2;
  } else {
    t.s0 = v[longest];
    t.s1 = v[(longest + 1) % 3];
  }
  return t;
}

// A copy of proper triangle t with its inward edge normals: for a counter-clockwise triangle
// seen along −n, n × edge points into the triangle, and |n × e| = |e| since n ⟂ e.
Primitive with_edge_normals(Primitive t) {
  for (int k = 0; k < 3; ++k) {
    t.m[k] = t.n.cross(t.v[(k + 1) % 3] - t.v[k]) / std::sqrt(t.len2[k]);
  }
  return t;
}

TriTriResult point_result(const Vec3& x, bool coplanar) { return {true, coplanar, x, x}; }

// Signed distance snapped to zero within the tolerance.
Real snap(Real d, Real eps) { return std::abs(d) <= eps ? 0 : d; }

bool inside_widened(const Primitive& t, const Vec3& x, Real eps) {
  for (int k = 0; k < 3; ++k) {
    if (t.m[k].dot(x - t.v[k]) < -eps) return false;
  }
  return true;
}

// Cyrus–Beck clipping of s(u) = s0 + u·(s1 − s0), u ∈ [u0, u1], against the three edge
// half-planes of t moved outward by `widen`: f_k(u) = m_k·(s(u) − v_k) + widen ≥ 0. Returns
// false when nothing is left.
bool clip_segment(const Vec3& s0, const Vec3& s1, const Primitive& t, Real widen, Real& u0,
                  Real& u1) {
  const Vec3 dir = s1 - s0;
  for (int k = 0; k < 3; ++k) {
    const Real f0 = t.m[k].dot(s0 - t.v[k]) + widen;
    const Real fd = t.m[k].dot(dir);
    if (fd == 0) {
      if (f0 < 0) return false;
      continue;
    }
    const Real u = -f0 / fd;
    if (fd > 0) {
      u0 = std::max(u0, u);
    } else {
      u1 = std::min(u1, u);
    }
    if (u0 > u1) return false;
  }
  return true;
}

// Segment (or point, s0 = s1) against a proper triangle.
TriTriResult segment_triangle(const Vec3& s0, const Vec3& s1, const Primitive& t, Real eps) {
  const Real d0 = snap(t.n.dot(s0 - t.v[0]), eps);
  const Real d1 = snap(t.n.dot(s1 - t.v[0]), eps);
  if (d0 == 0 && d1 == 0) {
    // In the plane: decide with the widened triangle (touching counts), report the exact clip
    // when it is not empty.
    Real u0 = 0;
    Real u1 = 1;
    if (!clip_segment(s0, s1, t, eps, u0, u1)) return {false, true, Vec3::Zero(), Vec3::Zero()};
    Real e0 = 0;
    Real e1 = 1;
    if (clip_segment(s0, s1, t, 0, e0, e1)) {
      u0 = e0;
      u1 = e1;
    }
    return {true, true, s0 + u0 * (s1 - s0), s0 + u1 * (s1 - s0)};
  }
  if ((d0 > 0 && d1 > 0) || (d0 < 0 && d1 < 0)) return {};
  // One crossing: an end on the plane, or strictly opposite signs (d0 − d1 ≠ 0).
  const Vec3 x = d0 == 0 ? s0 : d1 == 0 ? s1 : Vec3(s0 + (d0 / (d0 - d1)) * (s1 - s0));
  if (!inside_widened(t, x, eps)) return {};
  return point_result(x, false);
}

// Two segments (either may be a point).
TriTriResult segment_segment(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                             Real eps) {
  const SegmentSegmentClosest c = closest_points_segment_segment(p0, p1, q0, q1);
  if (c.distance_squared > eps * eps) return {};
  const Vec3 dp = p1 - p0;
  const Vec3 dq = q1 - q0;
  const Real lp2 = dp.squaredNorm();
  const Real lq2 = dq.squaredNorm();
  if (lp2 > 0 && lq2 > 0 &&
      dp.cross(dq).squaredNorm() <= kDegenerateRatio * kDegenerateRatio * lp2 * lq2) {
    // Collinear and touching: the overlap of the two on p's line.
    const Real s_a = (q0 - p0).dot(dp) / lp2;
    const Real s_b = (q1 - p0).dot(dp) / lp2;
    const Real lo = std::max(Real{0}, std::min(s_a, s_b));
    const Real hi = std::min(Real{1}, std::max(s_a, s_b));
    if (lo <= hi) return {true, true, p0 + lo * dp, p0 + hi * dp};
  }
  return point_result(0.5 * (c.on_p + c.on_q), true);
}

// The trace of proper triangle t on the other plane, given its vertices' snapped signed
// distances d to that plane (not all zero, not all of one strict sign): the vertices on the
// plane and the crossings of edges with strictly opposite signs. At most two points.
std::pair<Vec3, Vec3> trace(const Primitive& t, const std::array<Real, 3>& d) {
  std::array<Vec3, 2> pts;
  int count = 0;
  for (int i = 0; i < 3 && count < 2; ++i) {
    if (d[i] == 0) pts[count++] = t.v[i];
  }
  for (int i = 0; i < 3 && count < 2; ++i) {
    const int j = (i + 1) % 3;
    if ((d[i] > 0 && d[j] < 0) || (d[i] < 0 && d[j] > 0)) {
      pts[count++] = t.v[i] + (d[i] / (d[i] - d[j])) * (t.v[j] - t.v[i]);
    }
  }
  if (count == 1) pts[1] = pts[0];
  return {pts[0], pts[1]};
}

using Polygon = std::array<Vec3, 24>;

// Sutherland–Hodgman clipping of triangle `other` by the three edge half-planes of `base`, each
// moved outward by `widen`; writes the clipped polygon to `out` and returns its vertex count.
// Each clip at most doubles the count (3 → 6 → 12 → 24), and a convex input only adds one, so
// 24 slots always suffice.
int clip_by_triangle(const Primitive& base, const Primitive& other, Real widen, Polygon& out) {
  Polygon tmp;
  for (int i = 0; i < 3; ++i) tmp[i] = other.v[i];
  // Three passes alternate tmp → out → tmp → out, so the result ends in `out`.
  Polygon* in = &tmp;
  Polygon* next = &out;
  int n = 3;
  for (int k = 0; k < 3; ++k) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3& cur = (*in)[i];
      const Vec3& nxt = (*in)[(i + 1) % n];
      const Real fc = base.m[k].dot(cur - base.v[k]) + widen;
      const Real fn = base.m[k].dot(nxt - base.v[k]) + widen;
      if (fc >= 0) (*next)[m++] = cur;
      if ((fc >= 0) != (fn >= 0)) (*next)[m++] = cur + (fc / (fc - fn)) * (nxt - cur);
    }
    n = m;
    std::swap(in, next);
  }
  return n;
}

// Both triangles in one plane: clip `other` against the edge half-planes of `base`. The decision
// uses half-planes widened by the tolerance (so touching counts); the chord is taken from the
// exact clip when that is non-empty, and from the widened one (a sliver within the tolerance of
// the touching point or edge) when the triangles only touch.
TriTriResult coplanar_overlap(const Primitive& base, const Primitive& other, Real eps) {
  Polygon poly;
  int n = clip_by_triangle(base, other, eps, poly);
  if (n == 0) return {false, true, Vec3::Zero(), Vec3::Zero()};
  Polygon exact;
  const int n_exact = clip_by_triangle(base, other, 0, exact);
  if (n_exact > 0) {
    poly = exact;
    n = n_exact;
  }
  // Longest chord: the two polygon vertices farthest apart.
  int bi = 0;
  int bj = 0;
  Real best = -1;
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      const Real d2 = (poly[i] - poly[j]).squaredNorm();
      if (d2 > best) {
        best = d2;
        bi = i;
        bj = j;
      }
    }
  }
  return {true, true, poly[bi], poly[bj]};
}

TriTriResult triangle_triangle(const Primitive& a, const Primitive& b, Real size, Real eps) {
  std::array<Real, 3> d_b{};  // B's vertices to A's plane
  std::array<Real, 3> d_a{};  // A's vertices to B's plane
  for (int i = 0; i < 3; ++i) {
    d_b[i] = snap(a.n.dot(b.v[i] - a.v[0]), eps);
    d_a[i] = snap(b.n.dot(a.v[i] - b.v[0]), eps);
  }
  const auto all_zero = [](const std::array<Real, 3>& d) {
    return d[0] == 0 && d[1] == 0 && d[2] == 0;
  };
  const auto one_side = [](const std::array<Real, 3>& d) {
    return (d[0] > 0 && d[1] > 0 && d[2] > 0) || (d[0] < 0 && d[1] < 0 && d[2] < 0);
  };
  const bool b_in_a = all_zero(d_b);
  const bool a_in_b = all_zero(d_a);
  if (b_in_a || a_in_b) {
    // Clip the triangle lying in the other's plane against that (base) triangle; when both lie
    // in each other's plane, the larger one's plane is the better-determined base.
    const bool base_a = b_in_a && (!a_in_b || a.area2_sq >= b.area2_sq);
    return base_a ? coplanar_overlap(with_edge_normals(a), b, eps)
                  : coplanar_overlap(with_edge_normals(b), a, eps);
  }
  if (one_side(d_b) || one_side(d_a)) return {};

  const auto [a0, a1] = trace(a, d_a);
  const auto [b0, b1] = trace(b, d_b);
  const Real len_a = (a1 - a0).norm();
  const Real len_b = (b1 - b0).norm();
  const Vec3 line = a.n.cross(b.n);
  const Real line_len = line.norm();  // sin of the angle between the planes
  // Ordering direction: nA × nB has error ~ε/sin θ, a trace's own direction ~ε·L/length; take
  // the better conditioned one. Both traces lie on the same line, so either orders them.
  const Real longest = std::max(len_a, len_b);
  Vec3 u;
  if (line_len > 0 && line_len * size >= longest) {
    u = line / line_len;
  } else if (longest > 0) {
    u = len_a >= len_b ? Vec3((a1 - a0) / len_a) : Vec3((b1 - b0) / len_b);
  } else {
    // Both traces are single points and the planes are parallel: they meet iff they coincide.
    if ((a0 - b0).squaredNorm() > eps * eps) return {};
    return point_result(0.5 * (a0 + b0), false);
  }
  Real ta0 = u.dot(a0);
  Real ta1 = u.dot(a1);
  Real tb0 = u.dot(b0);
  Real tb1 = u.dot(b1);
  Vec3 pa0 = a0;
  Vec3 pa1 = a1;
  Vec3 pb0 = b0;
  Vec3 pb1 = b1;
  if (ta0 > ta1) {
    std::swap(ta0, ta1);
    std::swap(pa0, pa1);
  }
  if (tb0 > tb1) {
    std::swap(tb0, tb1);
    std::swap(pb0, pb1);
  }
  const Real lo = std::max(ta0, tb0);
  const Real hi = std::min(ta1, tb1);
  const Vec3& p_lo = ta0 >= tb0 ? pa0 : pb0;
  const Vec3& p_hi = ta1 <= tb1 ? pa1 : pb1;
  if (lo > hi + eps) return {};
  if (lo > hi) return point_result(0.5 * (p_lo + p_hi), false);  // touching within tolerance
  return {true, false, p_lo, p_hi};
}

}  // namespace

TriTriResult intersect_triangles(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                                 const Vec3& b1, const Vec3& b2) {
  // Work relative to a0 so that the tolerance follows the pair's size, not its distance from the
  // origin.
  const Vec3 o = a0;
  const std::array<Vec3, 6> v = {Vec3::Zero(), a1 - o, a2 - o, b0 - o, b1 - o, b2 - o};
  // L: the largest side of the pair's bounding box (the same for either argument order).
  Vec3 lo = v[0];
  Vec3 hi = v[0];
  for (const Vec3& x : v) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  for (const Vec3& x : v) {
    if (!x.allFinite()) return {};  // before min/max, which may drop a NaN
  }
  const Real size = (hi - lo).maxCoeff();
  const Real eps = kTriTriTolerance * size;

  // Möller's early rejection: all of one triangle strictly on one side of the other's plane.
  // Testing B against A's plane before B's normal is even computed saves most of the work for
  // separated pairs (valid whatever B is, degenerate or not).
  const auto strictly_one_side = [eps](const Primitive& t, const Vec3& x0, const Vec3& x1,
                                       const Vec3& x2) {
    const Real d0 = t.n.dot(x0 - t.v[0]);
    const Real d1 = t.n.dot(x1 - t.v[0]);
    const Real d2 = t.n.dot(x2 - t.v[0]);
    return (d0 > eps && d1 > eps && d2 > eps) || (d0 < -eps && d1 < -eps && d2 < -eps);
  };
  const Primitive a = make_primitive(v.data());
  if (a.is_triangle && strictly_one_side(a, v[3], v[4], v[5])) return {};
  const Primitive b = make_primitive(v.data() + 3);
  if (b.is_triangle && strictly_one_side(b, v[0], v[1], v[2])) return {};
  TriTriResult r;
  if (a.is_triangle && b.is_triangle) {
    r = triangle_triangle(a, b, size, eps);
  } else if (a.is_triangle) {
    r = segment_triangle(b.s0, b.s1, with_edge_normals(a), eps);
  } else if (b.is_triangle) {
    r = segment_triangle(a.s0, a.s1, with_edge_normals(b), eps);
  } else {
    r = segment_segment(a.s0, a.s1, b.s0, b.s1, eps);
  }
  if (!r.intersects) return {false, r.coplanar, Vec3::Zero(), Vec3::Zero()};
  r.p += o;
  r.q += o;
  return r;
}

}  // namespace trocar
