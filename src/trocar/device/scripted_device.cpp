#include "trocar/device/scripted_device.h"

#include <utility>

namespace trocar {

ScriptedDevice::ScriptedDevice(KeyframeMotion motion, Real max_force, Real damping)
    : PlaybackDevice("scripted", max_force, damping), motion_(std::move(motion)) {
  specs_.workspace = Vec3(0.16, 0.12, 0.07);  // Touch-class desktop workspace
}

PlaybackDevice::Played ScriptedDevice::play(double now_s) {
  constexpr double h = 5e-4;  // half-width of the velocity's central difference (s)
  const MotionSample s = motion_.sample(now_s);
  const Vec3 velocity =
      (motion_.sample(now_s + h).pose.translation - motion_.sample(now_s - h).pose.translation) / (2 * h);
  return {s.pose, s.jaw, velocity};
}

}  // namespace trocar
