#include "trocar/geometry/segment_triangle.h"

#include <cmath>

namespace trocar {

bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 d = q - p;
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const Real det = e1.dot(h);
  // Parallel to the plane (or a degenerate triangle), relative to the sizes involved.
  if (!(std::abs(det) > 1e-12 * d.norm() * e1.norm() * e2.norm())) return false;
  const Real f = 1 / det;
  const Vec3 s = p - a;
  const Real u = f * s.dot(h);
  if (u < 0 || u > 1) return false;
  const Vec3 r = s.cross(e1);
  const Real v = f * d.dot(r);
  if (v < 0 || u + v > 1) return false;
  const Real t = f * e2.dot(r);
  return t >= 0 && t <= 1;
}

}  // namespace trocar
