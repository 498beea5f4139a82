#pragma once
/// The `scripted` driver: a scene's keyframes played at the runtime's clock, as if a trainee's
/// hand followed them (the device side of today's `motion`). Forces sent to it are counted.
#include "trocar/core/motion.h"
#include "trocar/device/playback_device.h"

namespace trocar {

/// Samples a KeyframeMotion at read()'s time; velocity by central difference over 1 ms.
class ScriptedDevice final : public PlaybackDevice {
 public:
  /// Defaults as a Touch-class desktop device.
  explicit ScriptedDevice(KeyframeMotion motion, Real max_force = 3.3, Real damping = 2.0);

 private:
  Played play(double now_s) override;
  KeyframeMotion motion_;
};

}  // namespace trocar
