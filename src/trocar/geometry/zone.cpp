#include "trocar/geometry/zone.h"

#include <cmath>

namespace trocar {

Vec3 NamedZone::normal() const {
  // Newell's method: robust for any simple planar polygon (Sutherland et al. 1974; Ericson §12.5).
  Vec3 n = Vec3::Zero();
  const std::size_t k = polygon.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % k];
    n += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()), (a.x() - b.x()) * (a.y() + b.y()));
  }
  const Real len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

bool NamedZone::contains(const Vec3& p) const {
  if (polygon.size() < 3) return false;
  const Vec3 n = normal();
  if (n.isZero()) return false;
  const Real height = (p - polygon[0]).dot(n);
  if (std::abs(height) > depth) return false;
  // Inside test in the plane: the point is inside when it lies on the same side of every edge of
  // a convex polygon; for a general simple polygon use the crossing number in a 2D frame.
  const Vec3 u = (polygon[1] - polygon[0]).normalized();
  const Vec3 v = n.cross(u);
  const Vec3 q = p - height * n;
  auto to2 = [&](const Vec3& x) { return Vec2((x - polygon[0]).dot(u), (x - polygon[0]).dot(v)); };
  const Vec2 pq = to2(q);
  bool inside = false;
  const std::size_t k = polygon.size();
  for (std::size_t i = 0, j = k - 1; i < k; j = i++) {
    const Vec2 a = to2(polygon[i]);
    const Vec2 b = to2(polygon[j]);
    if ((a.y() > pq.y()) != (b.y() > pq.y()) && pq.x() < (b.x() - a.x()) * (pq.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

const NamedZone* zone_containing(const std::vector<NamedZone>& zones, const Vec3& p) {
  for (const NamedZone& z : zones)
    if (z.contains(p)) return &z;
  return nullptr;
}

}  // namespace trocar
