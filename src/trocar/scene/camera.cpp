#include "trocar/scene/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace trocar {
namespace {

constexpr Real kDeg = std::numbers::pi / 180.0;

/// gluLookAt: rows are the eye's right, up and backward axes.
Eigen::Matrix4f look_at(const Vec3& eye, const Vec3& forward, const Vec3& up) {
  const Vec3 f = forward.normalized();
  const Vec3 s = f.cross(up).normalized();
  const Vec3 u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m.cast<float>();
}

/// gluPerspective with a vertical field of view.
Eigen::Matrix4f perspective(Real fov_deg, Real aspect, Real near_clip, Real far_clip) {
  const Real f = 1.0 / std::tan(0.5 * fov_deg * kDeg);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far_clip + near_clip) / (near_clip - far_clip);
  m(2, 3) = 2 * far_clip * near_clip / (near_clip - far_clip);
  m(3, 2) = -1;
  return m.cast<float>();
}

struct Bounds {
  Vec3 centre = Vec3::Zero();
  Real radius = 0.05;
};

Bounds tissue_bounds(const World& world) {
  Vec3 lo = Vec3::Constant(1e30), hi = Vec3::Constant(-1e30);
  bool any = false;
  for (const auto& t : world.tissues)
    for (const Vec3& p : t->state.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      any = true;
    }
  Bounds b;
  if (!any) return b;
  b.centre = 0.5 * (lo + hi);
  b.radius = std::max(0.5 * (hi - lo).norm(), 1e-3);
  return b;
}

}  // namespace

Eigen::Vector3d CameraView::project(const Vec3& p, int width, int height) const {
  const Eigen::Vector4d clip = (projection * view).cast<double>() * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  if (clip.w() <= 0) return {0, 0, -1};
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  return {(ndc.x() + 1) * 0.5 * width, (1 - ndc.y()) * 0.5 * height, (ndc.z() + 1) * 0.5};
}

void laparoscope_eye(const CameraSpec& spec, Vec3& eye, Vec3& forward, Vec3& up) {
  const Vec3 shaft = (spec.target - spec.port).normalized();
  const Real insertion = spec.insertion > 0 ? spec.insertion : 0.5 * (spec.target - spec.port).norm();
  eye = spec.port + insertion * shaft;
  // The lens tilts the line of sight by angle_deg from the shaft, towards the monitor's up turned
  // by roll about the shaft (a 30° scope looks "up" at roll 0, as its light post points down).
  const Vec3 monitor_up = orthogonal_towards(shaft, spec.up);
  const Vec3 tilt = Eigen::AngleAxisd(spec.roll_deg * kDeg, shaft) * monitor_up;
  forward = (std::cos(spec.angle_deg * kDeg) * shaft + std::sin(spec.angle_deg * kDeg) * tilt).normalized();
  // The camera head stays level: the image's up is the scene's up, not the lens's.
  up = orthogonal_towards(forward, spec.up);
}

CameraView make_camera_view(const CameraSpec& spec, Real aspect) {
  CameraView v;
  if (spec.kind == CameraKind::kLaparoscope) {
    laparoscope_eye(spec, v.eye, v.forward, v.up);
  } else {
    // Orbit: yaw about `up`, pitch above the plane normal to it.
    const Vec3 side = orthogonal_towards(spec.up, Vec3(1, 0, 0));
    const Vec3 ahead = spec.up.cross(side);
    const Real yaw = spec.yaw_deg * kDeg, pitch = spec.pitch_deg * kDeg;
    const Vec3 out = std::cos(pitch) * (std::cos(yaw) * side + std::sin(yaw) * ahead) + std::sin(pitch) * spec.up;
    v.eye = spec.target + spec.distance * out;
    v.forward = -out.normalized();
    v.up = orthogonal_towards(v.forward, spec.up);
  }
  v.near_clip = spec.near_clip;
  v.far_clip = spec.far_clip;
  v.view = look_at(v.eye, v.forward, v.up);
  v.projection = perspective(spec.fov_deg, aspect, spec.near_clip, spec.far_clip);
  return v;
}

CameraSpec default_camera(const World& world) {
  const Bounds b = tissue_bounds(world);
  Vec3 side = Vec3(0, 0, 1);
  if (!world.instruments.empty()) {
    const Instrument& inst = world.instruments[0].instrument;
    const Vec3 back = inst.top_world() - inst.world_obb().center;
    if (back.norm() > 1e-9) side = back.normalized();
  }
  const Vec3 across = orthogonal_towards(side, Vec3(1, 0, 0));
  const Vec3 from = (std::cos(35 * kDeg) * side + std::sin(35 * kDeg) * across).normalized();
  CameraSpec s;
  s.name = "scope";
  s.kind = CameraKind::kLaparoscope;
  s.fov_deg = 70;
  // The nearest eye that sees every tissue vertex within the vertical field (so within the wider
  // horizontal one too): a vertex at height h off the axis and a ahead of the centre needs the eye
  // h / tan(fov/2) + a from the centre; 5 % margin. The bounding sphere alone frames elongated
  // organs at a quarter of the frame or less.
  const Real t = std::tan(0.5 * s.fov_deg * kDeg);
  Real distance = 0;
  for (const auto& tissue : world.tissues)
    for (const Vec3& p : tissue->state.positions) {
      const Vec3 r = p - b.centre;
      const Real ahead = r.dot(from);
      distance = std::max(distance, (r - ahead * from).norm() / t + ahead);
    }
  distance = 1.05 * std::max(distance, b.radius / t * 0.1);
  s.target = b.centre;
  s.port = b.centre + 2 * distance * from;
  s.insertion = distance;
  s.up = orthogonal_towards(from, Vec3(0, 1, 0));
  s.near_clip = std::max(1e-4, 0.01 * distance);
  s.far_clip = 20 * distance;
  return s;
}

CameraSpec default_orbit_camera(const World& world) {
  const Bounds b = tissue_bounds(world);
  CameraSpec s;
  s.name = "orbit";
  s.kind = CameraKind::kOrbit;
  s.target = b.centre;
  s.distance = 3 * b.radius;
  s.yaw_deg = -60;
  s.pitch_deg = 35;
  s.near_clip = std::max(1e-4, 0.01 * b.radius);
  s.far_clip = 50 * b.radius;
  return s;
}

}  // namespace trocar
