#include "trocar/instrument/instrument.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace trocar {

Vec3 shaft_axis(const Obb& box, const Vec3& shaft_direction) {
  const Real len = shaft_direction.norm();
  if (len > 0 && std::isfinite(len)) return shaft_direction / len;
  // auto: long axis a_0, signed so that the tip (the end nearer the local origin) is behind.
  const Vec3 a0 = box.axes.col(0);
  return a0.dot(Vec3::Zero() - box.center) <= 0 ? a0 : Vec3(-a0);
}

std::uint32_t find_top_vertex(std::span<const Vec3> points, const Obb& box, const Vec3& shaft_direction) {
  if (points.empty()) return 0;
  const Vec3 u = shaft_axis(box, shaft_direction);
  Real best = -std::numeric_limits<Real>::infinity();
  for (const Vec3& p : points) best = std::max(best, u.dot(p));
  // Ties within 1e-9 of the box's size: nearest to the axis line c + s·u, then lowest index.
  const Real tol = 1e-9 * std::max(Real{2} * box.half_extents.maxCoeff(), std::numeric_limits<Real>::min());
  std::uint32_t top = 0;
  Real best_radial = std::numeric_limits<Real>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (u.dot(points[i]) < best - tol) continue;
    const Vec3 r = points[i] - box.center;
    const Real radial = (r - u.dot(r) * u).squaredNorm();
    if (radial < best_radial) {
      best_radial = radial;
      top = static_cast<std::uint32_t>(i);
    }
  }
  return top;
}

Vec3 angular_velocity_between(const Quat& q0, const Quat& q1, Real dt) {
  if (!(dt > 0) || !std::isfinite(dt)) return Vec3::Zero();
  Quat q = q1 * q0.conjugate();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // shortest way round
  const Vec3 v = q.vec();
  const Real s = v.norm();
  if (!std::isfinite(s)) return Vec3::Zero();
  // q = (cos(θ/2), sin(θ/2)·axis): θ = 2·atan2(|v|, w); for tiny |v|, θ·axis → 2v (sin x ≈ x).
  if (s < 1e-12) return (Real{2} / dt) * v;
  const Real angle = Real{2} * std::atan2(s, q.w());
  return (angle / (s * dt)) * v;
}

Instrument::Instrument(TriMesh local_mesh, const Vec3& shaft_direction)
    : mesh_(std::move(local_mesh)),
      world_(mesh_.positions),
      jaw_flags_(mesh_.triangles.size(), 0) {
  local_obb_ = Obb::fit_pca(mesh_.positions);
  world_obb_ = local_obb_;
  top_ = find_top_vertex(mesh_.positions, local_obb_, shaft_direction);
  shaft_ = shaft_axis(local_obb_, shaft_direction);
  if (!shaft_.allFinite() || !(shaft_.squaredNorm() > 0)) shaft_ = Vec3::UnitZ();  // no mesh: a zero box
}

void Instrument::set_port(const Vec3& world_point) {
  if (!world_point.allFinite()) return;
  port_ = world_point;
  has_port_ = true;
}

Real Instrument::port_height(const Pose& pose) const {
  if (!has_port_) return std::numeric_limits<Real>::infinity();
  return shaft_.dot(pose.rotation.conjugate() * (port_ - pose.translation));
}

void Instrument::set_top_vertex(std::uint32_t vertex) {
  if (vertex < mesh_.positions.size()) top_ = vertex;
}

void Instrument::update_world() {
  const Mat3 r = pose_.rotation_matrix();
  const Vec3 t = pose_.translation;
  for (std::size_t i = 0; i < world_.size(); ++i) world_[i] = r * mesh_.positions[i] + t;
  world_obb_.center = r * local_obb_.center + t;
  world_obb_.axes = r * local_obb_.axes;
  world_obb_.half_extents = local_obb_.half_extents;
}

void Instrument::reset_pose(const Pose& pose) {
  pose_ = pose;
  previous_ = pose;
  linear_velocity_.setZero();
  angular_velocity_.setZero();
  update_world();
}

void Instrument::move_to(const Pose& pose, Real dt) {
  previous_ = pose_;
  pose_ = pose;
  if (dt > 0 && std::isfinite(dt)) {
    linear_velocity_ = (pose_.translation - previous_.translation) / dt;
    angular_velocity_ = angular_velocity_between(previous_.rotation, pose_.rotation, dt);
    if (!linear_velocity_.allFinite()) linear_velocity_.setZero();
  } else {
    linear_velocity_.setZero();
    angular_velocity_.setZero();
  }
  update_world();
}

void Instrument::set_jaw(Real closure) {
  jaw_ = closure >= 0 ? std::min(closure, Real{1}) : Real{0};  // NaN fails >= and gives 0
}

void Instrument::set_jaw_triangles(std::span<const std::uint32_t> triangles) {
  std::fill(jaw_flags_.begin(), jaw_flags_.end(), std::uint8_t{0});
  jaw_count_ = 0;
  for (const std::uint32_t t : triangles) {
    if (t < jaw_flags_.size() && jaw_flags_[t] == 0) {
      jaw_flags_[t] = 1;
      ++jaw_count_;
    }
  }
}

}  // namespace trocar
