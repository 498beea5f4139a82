#include "trocar/core/pose.h"

#include <cmath>

#include <numbers>

namespace trocar {

Pose Pose::from_euler_deg(const Vec3& translation, const Vec3& degrees_xyz) {
  const Vec3 r = degrees_xyz * (std::numbers::pi / 180.0);
  const Quat q = Eigen::AngleAxis<Real>(r.z(), Vec3::UnitZ()) *
                 Eigen::AngleAxis<Real>(r.y(), Vec3::UnitY()) *
                 Eigen::AngleAxis<Real>(r.x(), Vec3::UnitX());
  return {q.normalized(), translation};
}

Aabb Pose::apply(const Aabb& box) const {
  if (box.is_empty()) return box;
  // Centre moves as a point; the half-size grows by |R| (Arvo 1990).
  const Mat3 r = rotation_matrix();
  const Vec3 center = apply(box.center());
  const Vec3 half = r.cwiseAbs() * (0.5 * box.size());
  return {center - half, center + half};
}

Obb Pose::apply(const Obb& box) const {
  return {apply(box.center), rotation_matrix() * box.axes, box.half_extents};
}

Pose Pose::inverse() const {
  const Quat inv = rotation.conjugate();
  return {inv, -(inv * translation)};
}

Pose Pose::operator*(const Pose& other) const {
  return {(rotation * other.rotation).normalized(), rotation * other.translation + translation};
}

Vec3 orthogonal_towards(const Vec3& axis, const Vec3& hint) {
  Vec3 u = hint - hint.dot(axis) * axis;
  if (u.norm() < 1e-6) {
    const Vec3 other = std::abs(axis.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    u = other - other.dot(axis) * axis;
  }
  return u.normalized();
}

}  // namespace trocar
