#include "trocar/device/scripted_device.h"

#include <utility>

namespace trocar {

ScriptedDevice::ScriptedDevice(KeyframeMotion motion, Real max_force, Real damping, std::vector<ButtonPress> presses)
    : PlaybackDevice("scripted", max_force, damping), motion_(std::move(motion)), presses_(std::move(presses)) {
  specs_.workspace = Vec3(0.16, 0.12, 0.07);  // Touch-class desktop workspace
}

PlaybackDevice::Played ScriptedDevice::play(double now_s) {
  constexpr double h = 5e-4;  // half-width of the velocity's central difference (s)
  const MotionSample s = motion_.sample(now_s);
  const Vec3 velocity =
      (motion_.sample(now_s + h).pose.translation - motion_.sample(now_s - h).pose.translation) / (2 * h);
  std::uint32_t buttons = 0;
  for (const ButtonPress& p : presses_)  // a few per scene: a scan allocates nothing
    if (now_s >= p.t && now_s < (p.until >= 0 ? p.until : p.t + kPressTime)) buttons |= p.buttons;
  return {s.pose, s.jaw, velocity, buttons};
}

}  // namespace trocar
