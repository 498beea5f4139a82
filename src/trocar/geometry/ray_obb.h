#pragma once
/// Where a ray enters and leaves an oriented box (slab method).
#include "trocar/core/obb.h"
#include "trocar/core/types.h"

namespace trocar {

/// Result of intersect_ray_obb. Distances are along the normalised direction, so they are in
/// the box's unit (metres).
struct RayObbHit {
  bool hit = false;            ///< the ray {origin + t·d̂, t ≥ 0} meets the closed box
  bool origin_inside = false;  ///< origin lies in the closed box (then t_entry = 0)
  Real t_entry = 0;            ///< distance from origin to where the ray enters (0 if inside)
  Real t_exit = 0;             ///< distance from origin to where the ray leaves the box
  Vec3 entry = Vec3::Zero();   ///< origin + t_entry·d̂ (origin itself when inside)
  Vec3 exit = Vec3::Zero();    ///< origin + t_exit·d̂: the exit point (docs/response.md, step 5)
};

/// The ray from `origin` along `direction` (any non-zero length; it is normalised) against the
/// box. Slab method (Kay & Kajiya 1986; Ericson, Real-Time Collision Detection §5.3.3) in the
/// box's frame: per axis the ray is inside the slab |x_k| ≤ h_k for t between the two plane
/// crossings; the ray is in the box on the intersection of the three intervals and of t ≥ 0.
///  - origin inside: hit, origin_inside, t_entry = 0, t_exit = the exit distance (0 when the
///    origin is on a face and the ray points out).
///  - origin outside: hit when the ray passes through the box, with entry and exit; else !hit.
///  - a direction component exactly 0 in the box frame: that slab bounds nothing when the origin
///    is within it, and the ray misses otherwise (no 0/0).
///  - zero or non-finite direction, or non-finite origin: !hit (origin_inside still reported).
RayObbHit intersect_ray_obb(const Obb& box, const Vec3& origin, const Vec3& direction);

}  // namespace trocar
