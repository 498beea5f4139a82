#pragma once
/// Rigid transform: a rotation followed by a translation.
#include "trocar/core/aabb.h"
#include "trocar/core/obb.h"
#include "trocar/core/types.h"

namespace trocar {

/// x_world = rotation · x_local + translation. Rotation is a unit quaternion.
struct Pose {
  Quat rotation = Quat::Identity();     ///< unit quaternion
  Vec3 translation = Vec3::Zero();      ///< metres

  static Pose identity() { return {}; }
  /// R = Rz(c)·Ry(b)·Rx(a) for degrees [a, b, c] (about the fixed x, then y, then z axes;
  /// docs/scene.md "Meshes").
  static Pose from_euler_deg(const Vec3& translation, const Vec3& degrees_xyz);

  Vec3 apply(const Vec3& p) const { return rotation * p + translation; }  ///< a point
  Vec3 apply_vector(const Vec3& v) const { return rotation * v; }         ///< a direction
  /// The box holding the transformed box (exact for the box's corners).
  Aabb apply(const Aabb& box) const;
  /// The same box carried by this pose: centre moved, axes rotated, extents kept.
  Obb apply(const Obb& box) const;
  /// The inverse transform.
  Pose inverse() const;
  /// (this ∘ other)(x) = this(other(x)).
  Pose operator*(const Pose& other) const;
  /// The 3×3 rotation matrix.
  Mat3 rotation_matrix() const { return rotation.toRotationMatrix(); }
};

/// The unit vector orthogonal to the unit `axis` closest to `hint` (Gram–Schmidt); when the hint
/// is parallel to the axis, the one closest to x (or y, for an axis along x). Cameras and the
/// port pivot build their frames with it.
Vec3 orthogonal_towards(const Vec3& axis, const Vec3& hint);

}  // namespace trocar
