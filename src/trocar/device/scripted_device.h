#pragma once
/// The `scripted` driver: a scene's keyframes played at the runtime's clock, as if a trainee's
/// hand followed them (the device side of today's `motion`), and its buttons pressed at the
/// scene's scripted times (its "events": fire, exchange). Forces sent to it are counted.
#include <cstdint>
#include <vector>

#include "trocar/core/motion.h"
#include "trocar/device/playback_device.h"

namespace trocar {

/// A button press of a scripted device: `buttons` (DeviceInput::buttons bits) held down from `t`
/// (s on the runtime's clock) for ScriptedDevice::kPressTime.
struct ButtonPress {
  double t = 0;
  std::uint32_t buttons = 0;
  double until = -1;  ///< s: held down until then (the electrode's pedal); < 0: for kPressTime
};

/// Samples a KeyframeMotion at read()'s time; velocity by central difference over 1 ms.
class ScriptedDevice final : public PlaybackDevice {
 public:
  /// How long a scripted press holds its buttons (s): long enough for any haptic rate to see it,
  /// short enough that presses 0.1 s apart stay apart (the runtime acts on rising edges).
  static constexpr double kPressTime = 0.05;

  /// Defaults as a Touch-class desktop device.
  explicit ScriptedDevice(KeyframeMotion motion, Real max_force = 3.3, Real damping = 2.0,
                          std::vector<ButtonPress> presses = {});

 private:
  Played play(double now_s) override;
  KeyframeMotion motion_;
  std::vector<ButtonPress> presses_;
};

}  // namespace trocar
