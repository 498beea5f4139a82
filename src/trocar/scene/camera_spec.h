#pragma once
/// The scene's `"camera"` (docs/scene.md): a laparoscope entering through a port, or an orbit
/// camera. Plain data; the renderer turns it into view and projection matrices (render/camera.h).
#include <string>

#include "trocar/core/types.h"

namespace trocar {

/// What kind of camera a CameraSpec describes.
enum class CameraKind {
  kLaparoscope,  ///< a rigid scope through a port: the eye at its tip, looking along its shaft
                 ///< (0°) or tilted from it (30° scopes)
  kOrbit,        ///< a free camera orbiting a target
};

/// One entry of the scene's `"camera"`.
struct CameraSpec {
  std::string name = "scope";   ///< "name": what `--camera NAME` selects
  CameraKind kind = CameraKind::kLaparoscope;  ///< "type": "laparoscope" | "orbit"
  Vec3 port = Vec3::Zero();     ///< laparoscope "port": where the scope enters the body (m)
  Vec3 target = Vec3::Zero();   ///< "target": the shaft points at it (laparoscope); orbit centre
  /// laparoscope "insertion": the tip's distance from the port along the shaft (m); ≤ 0 = half
  /// the port–target distance.
  Real insertion = 0;
  Real angle_deg = 0;           ///< laparoscope "angle_deg": lens angle from the shaft axis (0, 30, 45)
  Real roll_deg = 0;            ///< laparoscope "roll_deg": rotation of the angled lens about the shaft
  Vec3 up = Vec3(0, 0, 1);      ///< "up": the direction shown upward on the monitor
  Real fov_deg = 70;            ///< "fov_deg": vertical field of view
  Real distance = 0.2;          ///< orbit "distance" (m)
  Real yaw_deg = 0;             ///< orbit "yaw_deg" about `up`
  Real pitch_deg = 30;          ///< orbit "pitch_deg" above the plane normal to `up`
  Real near_clip = 0.002;       ///< "near" (m)
  Real far_clip = 2.0;          ///< "far" (m)
};

}  // namespace trocar
