#include "trocar/geometry/ray_obb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace trocar {

RayObbHit intersect_ray_obb(const Obb& box, const Vec3& origin, const Vec3& direction) {
  RayObbHit r;
  const Vec3 o = box.to_local(origin);
  if (!o.allFinite()) return r;
  const Vec3 h = box.half_extents;
  r.origin_inside = (o.array().abs() <= h.array()).all();
  const Real len = direction.norm();
  if (!(len > 0) || !std::isfinite(len)) return r;
  const Vec3 dir = direction / len;
  const Vec3 d = box.axes.transpose() * dir;

  Real t_min = -std::numeric_limits<Real>::infinity();
  Real t_max = std::numeric_limits<Real>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (std::abs(o[k]) > h[k]) return r;  // parallel to the slab and outside it
      continue;
    }
    // Crossings of the planes x_k = −h_k and x_k = +h_k: o_k + t·d_k = ±h_k.
    Real t1 = (-h[k] - o[k]) / d[k];
    Real t2 = (h[k] - o[k]) / d[k];
    if (t1 > t2) std::swap(t1, t2);
    t_min = std::max(t_min, t1);
    t_max = std::min(t_max, t2);
  }
  const Real t_entry = std::max(t_min, Real{0});
  if (r.origin_inside) {
    // Rounding may put the exit a hair behind the origin when it sits on a face.
    r.hit = true;
    r.t_entry = 0;
    r.t_exit = std::max(t_max, Real{0});
  } else {
    if (t_max < t_entry) return r;
    r.hit = true;
    r.t_entry = t_entry;
    r.t_exit = t_max;
  }
  r.entry = origin + r.t_entry * dir;
  r.exit = origin + r.t_exit * dir;
  return r;
}

}  // namespace trocar
