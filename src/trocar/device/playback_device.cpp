#include "trocar/device/playback_device.h"

#include <cmath>
#include <utility>

namespace trocar {

PlaybackDevice::PlaybackDevice(std::string name, Real max_force, Real damping) {
  specs_.name = std::move(name);
  specs_.max_force = max_force;
  specs_.damping = damping;
}

DeviceStatus PlaybackDevice::read(double now_s, DeviceInput& input) {
  const Played p = play(now_s);
  input.pose = p.pose;
  input.jaw = p.jaw;
  input.velocity = p.velocity;
  input.angular_velocity = Vec3::Zero();
  input.buttons = p.buttons;
  input.timestamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  input.sequence = reads_.fetch_add(1, std::memory_order_relaxed) + 1;
  return DeviceStatus::kConnected;
}

void PlaybackDevice::write(const DeviceOutput& /*output*/) { forces_.fetch_add(1, std::memory_order_relaxed); }

DeviceCounters PlaybackDevice::counters() const {
  DeviceCounters c;
  c.samples = reads_.load(std::memory_order_relaxed);
  c.forces_sent = forces_.load(std::memory_order_relaxed);
  c.connections = 1;
  return c;
}

}  // namespace trocar
