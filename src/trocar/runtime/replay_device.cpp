#include "trocar/runtime/replay_device.h"

#include "trocar/core/error.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/recording.h"

namespace trocar {

ReplayDevice::ReplayDevice(const std::filesystem::path& recording, std::size_t instrument, Real max_force,
                           Real damping)
    : PlaybackDevice("replay " + recording.filename().string(), max_force, damping) {
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
}

PlaybackDevice::Played ReplayDevice::play(double now_s) {
  if (cursor_ > 0 && samples_[cursor_].t > now_s) cursor_ = 0;  // time went back: search again
  while (cursor_ + 1 < samples_.size() && samples_[cursor_ + 1].t <= now_s) ++cursor_;
  const Sample& s = samples_[cursor_];
  const std::size_t a = cursor_ > 0 ? cursor_ - 1 : cursor_;
  const std::size_t b = cursor_ + 1 < samples_.size() ? cursor_ + 1 : cursor_;
  const double span = samples_[b].t - samples_[a].t;
  const Vec3 velocity =
      span > 0 ? Vec3((samples_[b].pose.translation - samples_[a].pose.translation) / span) : Vec3::Zero();
  return {s.pose, s.jaw, velocity};
}

}  // namespace trocar
