#pragma once
/// Scripted instrument motion: keyframes of position, rotation and jaw closure.
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/pose.h"
#include "trocar/core/types.h"

namespace trocar {

/// One keyframe: where the instrument mesh's origin is at time t, its rotation and jaw closure.
struct Keyframe {
  Real t = 0;                         ///< time (s)
  Vec3 position = Vec3::Zero();       ///< world position of the instrument's local origin (m)
  Quat rotation = Quat::Identity();   ///< local → world rotation (unit)
  Real jaw = 0;                       ///< jaw closure, 0 open … 1 closed (dimensionless)
};

/// How the position moves between keyframes.
enum class Interpolation : std::uint8_t {
  kLinear,  ///< straight, at constant speed: the velocity jumps at every keyframe
  /// A cubic Hermite curve through the keyframes: the velocity is continuous, the acceleration
  /// bounded, as a hand's is (a scripted track that stands for a person; docs/scene.md).
  kSmooth,
};

/// What the motion prescribes at one time.
struct MotionSample {
  Pose pose;    ///< local → world
  Real jaw = 0; ///< closure 0..1
};

/// Piecewise motion through keyframes: position linearly or along a smooth curve (Interpolation),
/// jaw linearly, rotation by spherical linear interpolation (shorter arc); before the first
/// keyframe the first holds, after the last the last holds. Velocities are not stored: the
/// instrument derives them from the poses of consecutive steps (Instrument::move_to). No
/// keyframes: identity pose, jaw open.
class KeyframeMotion {
 public:
  KeyframeMotion() = default;
  /// Keyframes with strictly increasing t (the scene loader checks this; here unsorted input is
  /// sorted by t, stable).
  explicit KeyframeMotion(std::vector<Keyframe> keyframes, Interpolation interpolation = Interpolation::kLinear);
  /// The pose and jaw at time t (s). No allocation.
  MotionSample sample(Real t) const;
  /// The keyframes.
  std::span<const Keyframe> keyframes() const { return keyframes_; }
  /// Time of the last keyframe (s), 0 when none.
  Real end_time() const { return keyframes_.empty() ? 0 : keyframes_.back().t; }
  bool empty() const { return keyframes_.empty(); }  ///< no keyframes: the instrument stays where it is put
  Interpolation interpolation() const { return interpolation_; }

 private:
  std::vector<Keyframe> keyframes_;
  Interpolation interpolation_ = Interpolation::kLinear;
  std::vector<Vec3> tangents_;  ///< kSmooth: the velocity at each keyframe (m/s)
};

}  // namespace trocar
