#pragma once
/// Cameras (docs/render.md): the laparoscope — a rigid scope entering through a port, its eye at
/// the tip, looking along the shaft (0°) or tilted from it by the lens angle (30° scopes) — and a
/// free orbit camera. Pure math, no GL: tests project geometry with the same matrices.
#include <Eigen/Core>

#include "trocar/core/types.h"
#include "trocar/scene/camera_spec.h"
#include "trocar/sim/world.h"

namespace trocar {

/// A camera ready to draw with: OpenGL's right-handed eye space (looking down −z), clip space
/// from a symmetric perspective frustum.
struct CameraView {
  Vec3 eye = Vec3::Zero();        ///< m
  Vec3 forward = Vec3(0, 0, -1);  ///< unit viewing direction
  Vec3 up = Vec3(0, 1, 0);        ///< unit, orthogonal to forward
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();        ///< world → eye
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();  ///< eye → clip
  Real near_clip = 0.002;         ///< m
  Real far_clip = 2;              ///< m
  /// Where world point p lands in a width × height image: x right, y down, pixel centres at
  /// i + 0.5; z = the window depth in [0, 1]. w ≤ 0 (behind the eye) gives z < 0.
  Eigen::Vector3d project(const Vec3& p, int width, int height) const;
};

/// The view of a CameraSpec at the given aspect ratio (width / height).
CameraView make_camera_view(const CameraSpec& spec, Real aspect);

/// The scope tip's position and the viewing direction of a laparoscope spec (the lens angle
/// tilts the view from the shaft towards `up` turned by `roll_deg` about the shaft).
void laparoscope_eye(const CameraSpec& spec, Vec3& eye, Vec3& forward, Vec3& up);

/// A camera that frames the world when the scene names none: a 0° laparoscope entering on the
/// side of the first instrument's shaft, 35° off it so the instrument is seen, aimed at the
/// tissues' centre, with the whole tissue bounding sphere in its field of view.
CameraSpec default_camera(const World& world);

/// An orbit camera around the world's tissues (name "orbit"), the viewer's free camera.
CameraSpec default_orbit_camera(const World& world);

}  // namespace trocar
