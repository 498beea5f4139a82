#include "trocar/geometry/closest_point.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "trocar/geometry/tolerance.h"

namespace trocar {
namespace {

TriangleClosestPoint vertex_result(const Vec3& v, int k) {
  TriangleClosestPoint r;
  r.point = v;
  r.barycentric = Vec3::Zero();
  r.barycentric[k] = 1.0;
  r.feature = TriangleFeature::kVertex;
  r.index = k;
  return r;
}

// Point on edge k (from vertex k to vertex k+1) at parameter t ∈ (0, 1).
TriangleClosestPoint edge_result(const Vec3& from, const Vec3& to, int k, Real t) {
  if (t <= 0) return vertex_result(from, k);
  if (t >= 1) return vertex_result(to, (k + 1) % 3);
  TriangleClosestPoint r;
  r.point = from + t * (to - from);
  r.barycentric = Vec3::Zero();
  r.barycentric[k] = 1.0 - t;
  r.barycentric[(k + 1) % 3] = t;
  r.feature = TriangleFeature::kEdge;
  r.index = k;
  return r;
}

// The closest of the selected edges' closest points (edge k: vertex k → k+1); at least one edge
// must be selected. With all three it is exact for degenerate triangles (collinear or repeated
// vertices).
TriangleClosestPoint closest_on_edges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                      bool edge0, bool edge1, bool edge2) {
  const Vec3* v[3] = {&a, &b, &c};
  const bool use[3] = {edge0, edge1, edge2};
  TriangleClosestPoint best;
  Real best_d2 = std::numeric_limits<Real>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (!use[k]) continue;
    const Vec3& from = *v[k];
    const Vec3& to = *v[(k + 1) % 3];
    const TriangleClosestPoint r = edge_result(from, to, k, closest_point_on_segment(p, from, to));
    const Real d2k = (p - r.point).squaredNorm();
    if (d2k < best_d2 || best_d2 == std::numeric_limits<Real>::infinity()) {
      best = r;
      best_d2 = d2k;
    }
  }
  return best;
}

}  // namespace

Real closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real len2 = ab.squaredNorm();
  if (!(len2 > 0)) return 0;
  return std::clamp((p - a).dot(ab) / len2, Real{0}, Real{1});
}

TriangleClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                               const Vec3& c) {
  // Ericson §5.1.5 partitions space into the Voronoi regions of the face, the three edges and
  // the three vertices. The face region is where p's projection lies inside the triangle; there
  // the projection is the answer, elsewhere the nearest point of an edge facing p (whose line
  // separates the projection from the triangle), the vertex regions being that edge's ends.
  //
  // The book's dot-product region tests and the barycentric reconstruction a + v·ab + w·ac lose
  // ~ε·L/h relative accuracy on a sliver of length L and height h, i.e. an error ~ε·L²/h in the
  // point. We instead work in an orthonormal frame built by Gram–Schmidt on the longest edge:
  // coordinates (x, y) in the plane carry errors ~ε·L whatever the shape, and the face point
  // o + x·ê + y·ĝ is formed from them directly.
  const Vec3* v[3] = {&a, &b, &c};
  std::array<Real, 3> len2{};
  for (int k = 0; k < 3; ++k) len2[k] = (*v[(k + 1) % 3] - *v[k]).squaredNorm();
  const int l = static_cast<int>(std::max_element(len2.begin(), len2.end()) - len2.begin());
  const int l1 = (l + 1) % 3;
  const int l2 = (l + 2) % 3;
  const Real edge_len = std::sqrt(len2[l]);
  // Frame: ê along the longest edge v_l → v_l+1, ĝ toward the third vertex, in the plane.
  const Vec3& o = *v[l];
  if (!(edge_len > 0)) return closest_on_edges(p, a, b, c, true, true, true);
  const Vec3 e_hat = (*v[l1] - o) / edge_len;
  const Vec3 f = *v[l2] - o;
  const Real fx = f.dot(e_hat);
  const Vec3 g = f - fx * e_hat;
  const Real fy = g.norm();
  // Degenerate triangle (twice the area L·fy ≤ kDegenerateRatio·L², tolerance.h): its edges.
  if (!(fy > kDegenerateRatio * edge_len)) return closest_on_edges(p, a, b, c, true, true, true);
  const Vec3 g_hat = g / fy;
  const Vec3 q = p - o;
  const Real x = q.dot(e_hat);
  const Real y = q.dot(g_hat);
  // Local 2-D triangle P0 = (0, 0), P1 = (L, 0), P2 = (fx, fy), counter-clockwise (fy > 0).
  // Edge functions orient2d(P_i, P_i+1, X), each twice the area of a sub-triangle, so vertex
  // P_i+2's barycentric coordinate is its opposite function / (L·fy).
  const Real s0 = edge_len * y;                                  // edge P0P1, opposite P2
  const Real s1 = (fx - edge_len) * y - fy * (x - edge_len);     // edge P1P2, opposite P0
  const Real s2 = fy * x - fx * y;                               // edge P2P0, opposite P1
  if (s0 >= 0 && s1 >= 0 && s2 >= 0) {
    TriangleClosestPoint r;
    r.point = o + x * e_hat + y * g_hat;
    const Real area2 = edge_len * fy;
    r.barycentric[l] = s1 / area2;
    r.barycentric[l1] = s2 / area2;
    r.barycentric[l2] = s0 / area2;
    r.feature = TriangleFeature::kFace;
    r.index = 0;
    return r;
  }
  // Local edge P_i P_i+1 is triangle edge (l + i) mod 3.
  bool use[3] = {false, false, false};
  use[l] = s0 < 0;
  use[l1] = s1 < 0;
  use[l2] = s2 < 0;
  return closest_on_edges(p, a, b, c, use[0], use[1], use[2]);
}

SegmentSegmentClosest closest_points_segment_segment(const Vec3& p0, const Vec3& p1,
                                                     const Vec3& q0, const Vec3& q1) {
  // Ericson §5.1.9, ClosestPtSegmentSegment: minimise |p(s) − q(t)|² over [0,1]², first with t
  // free then clamping, handling a = 0 or e = 0 (points) separately.
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const Real a = d1.squaredNorm();
  const Real e = d2.squaredNorm();
  const Real f = d2.dot(r);
  Real s = 0;
  Real t = 0;
  if (a <= 0 && e <= 0) {
    s = t = 0;
  } else if (a <= 0) {
    t = std::clamp(f / e, Real{0}, Real{1});
  } else {
    const Real c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, Real{0}, Real{1});
    } else {
      const Real b = d1.dot(d2);
      const Real denom = a * e - b * b;  // = |d1 × d2|² ≥ 0
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, Real{0}, Real{1}) : 0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, Real{0}, Real{1});
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, Real{0}, Real{1});
      }
    }
  }
  SegmentSegmentClosest out;
  out.s = s;
  out.t = t;
  out.on_p = p0 + s * d1;
  out.on_q = q0 + t * d2;
  out.distance_squared = (out.on_p - out.on_q).squaredNorm();
  return out;
}

}  // namespace trocar
