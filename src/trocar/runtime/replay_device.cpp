#include "trocar/runtime/replay_device.h"

#include <cmath>

#include "trocar/core/error.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/recording.h"

namespace trocar {

ReplayDevice::ReplayDevice(const std::filesystem::path& recording, std::size_t instrument, Real max_force,
                           Real damping) {
  const Recording rec = read_recording(recording, false);
  if (instrument >= rec.header.instruments)
    throw FileError(recording.string(), FileLocation::none(),
                    "has " + std::to_string(rec.header.instruments) + " instrument(s); instrument " +
                        std::to_string(instrument) + " was asked for");
  samples_.reserve(rec.ticks.size());
  for (const TickRecord& t : rec.ticks) {
    const TickInstrument& ti = t.instrument[instrument];
    if (ti.status != static_cast<std::uint32_t>(DeviceStatus::kConnected)) continue;
    samples_.push_back({double(t.time_ns) * 1e-9, from_words(ti.device_pose), ti.jaw});
  }
  if (samples_.empty())
    throw FileError(recording.string(), FileLocation::none(),
                    "holds no connected haptic tick for instrument " + std::to_string(instrument));
  specs_.name = "replay " + recording.filename().string();
  specs_.max_force = max_force;
  specs_.damping = damping;
}

DeviceStatus ReplayDevice::read(double now_s, DeviceInput& input) {
  if (cursor_ > 0 && samples_[cursor_].t > now_s) cursor_ = 0;  // time went back: search again
  while (cursor_ + 1 < samples_.size() && samples_[cursor_ + 1].t <= now_s) ++cursor_;
  const Sample& s = samples_[cursor_];
  input.pose = s.pose;
  input.jaw = s.jaw;
  const std::size_t a = cursor_ > 0 ? cursor_ - 1 : cursor_;
  const std::size_t b = cursor_ + 1 < samples_.size() ? cursor_ + 1 : cursor_;
  const double span = samples_[b].t - samples_[a].t;
  input.velocity = span > 0 ? Vec3((samples_[b].pose.translation - samples_[a].pose.translation) / span) : Vec3::Zero();
  input.timestamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  input.sequence = reads_.fetch_add(1, std::memory_order_relaxed) + 1;
  return DeviceStatus::kConnected;
}

void ReplayDevice::write(const DeviceOutput& /*output*/) { forces_.fetch_add(1, std::memory_order_relaxed); }

DeviceCounters ReplayDevice::counters() const {
  DeviceCounters c;
  c.samples = reads_.load(std::memory_order_relaxed);
  c.forces_sent = forces_.load(std::memory_order_relaxed);
  c.connections = 1;
  return c;
}

}  // namespace trocar
