#include "trocar/geometry/segment_plane.h"

#include <cmath>

namespace trocar {

SegmentPlaneHit intersect_segment_plane(const Vec3& a, const Vec3& b, const Vec3& plane_point,
                                        const Vec3& plane_normal, Real tolerance) {
  SegmentPlaneHit hit;
  const Real len = plane_normal.norm();
  if (!(len > 0) || !std::isfinite(len)) return hit;
  const Vec3 n = plane_normal / len;
  Real da = n.dot(a - plane_point);
  Real db = n.dot(b - plane_point);
  if (!std::isfinite(da) || !std::isfinite(db)) return hit;
  if (std::abs(da) <= tolerance) da = 0;
  if (std::abs(db) <= tolerance) db = 0;
  if (da == 0 && db == 0) {
    hit.kind = SegmentPlaneKind::kInPlane;
    hit.point = a;
    return hit;
  }
  if ((da > 0 && db > 0) || (da < 0 && db < 0)) return hit;
  hit.kind = SegmentPlaneKind::kPoint;
  if (da == 0) {
    hit.point = a;
  } else if (db == 0) {
    hit.t = 1;
    hit.point = b;
  } else {
    // Strictly opposite signs: |da − db| = |da| + |db| > 0, and t ∈ (0, 1).
    hit.t = da / (da - db);
    hit.point = a + hit.t * (b - a);
  }
  return hit;
}

}  // namespace trocar
