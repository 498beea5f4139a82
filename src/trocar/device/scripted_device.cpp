#include "trocar/device/scripted_device.h"

#include <cmath>

namespace trocar {

ScriptedDevice::ScriptedDevice(KeyframeMotion motion, Real max_force, Real damping) : motion_(std::move(motion)) {
  specs_.name = "scripted";
  specs_.max_force = max_force;
  specs_.damping = damping;
  specs_.workspace = Vec3(0.16, 0.12, 0.07);  // Touch-class desktop workspace
}

DeviceStatus ScriptedDevice::read(double now_s, DeviceInput& input) {
  constexpr double h = 5e-4;  // half-width of the velocity's central difference (s)
  const MotionSample s = motion_.sample(now_s);
  input.pose = s.pose;
  input.jaw = s.jaw;
  input.velocity = (motion_.sample(now_s + h).pose.translation - motion_.sample(now_s - h).pose.translation) / (2 * h);
  input.angular_velocity = Vec3::Zero();
  input.buttons = 0;
  input.timestamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  input.sequence = samples_.fetch_add(1, std::memory_order_relaxed) + 1;
  return DeviceStatus::kConnected;
}

void ScriptedDevice::write(const DeviceOutput& /*output*/) { forces_.fetch_add(1, std::memory_order_relaxed); }

DeviceCounters ScriptedDevice::counters() const {
  DeviceCounters c;
  c.samples = samples_.load(std::memory_order_relaxed);
  c.forces_sent = forces_.load(std::memory_order_relaxed);
  c.connections = 1;
  return c;
}

}  // namespace trocar
