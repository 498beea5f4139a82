#include "trocar/geometry/barycentric.h"

#include <algorithm>

#include "trocar/geometry/tolerance.h"

namespace trocar {

Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const Vec3 n = ab.cross(ac);
  const Real n2 = n.squaredNorm();

  const Real l_ab = ab.squaredNorm();
  const Real l_bc = (c - b).squaredNorm();
  const Real l_ca = ac.squaredNorm();
  const Real longest2 = std::max({l_ab, l_bc, l_ca});
  // Degeneracy: |n| ≤ k·L² ⇔ |n|² ≤ k²·L⁴ (squares avoid the square roots).
  if (n2 > kDegenerateRatio * kDegenerateRatio * longest2 * longest2 && n2 > 0) {
    // Cramer's rule in 3D (Ericson, Real-Time Collision Detection §3.4, written with cross
    // products): for the projection a + v·ab + w·ac of p, ap × ac = v (ab × ac) + (normal part)
    // and ab × ap = w (ab × ac) + ..., so dotting with n = ab × ac gives v and w. Using n·n
    // instead of d00·d11 − d01² avoids the cancellation for thin triangles.
    const Real v = n.dot(ap.cross(ac)) / n2;
    const Real w = n.dot(ab.cross(ap)) / n2;
    return {1.0 - v - w, v, w};
  }
  if (longest2 <= 0) return {1.0, 0.0, 0.0};
  // Segment: project on the longest edge i→j.
  const Vec3* vi = &a;
  const Vec3* vj = &b;
  int i = 0;
  int j = 1;
  if (l_bc >= l_ab && l_bc >= l_ca) {
    vi = &b; vj = &c; i = 1; j = 2;
  } else if (l_ca >= l_ab && l_ca >= l_bc) {
    vi = &c; vj = &a; i = 2; j = 0;
  }
  const Vec3 e = *vj - *vi;
  const Real t = (p - *vi).dot(e) / e.squaredNorm();
  Vec3 result = Vec3::Zero();
  result[i] = 1.0 - t;
  result[j] = t;
  return result;
}

}  // namespace trocar
