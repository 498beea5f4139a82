#pragma once
/// The `replay` driver: the device poses of a recorded session (its haptic ticks), played back
/// at the runtime's clock, so a recorded hand motion can drive a new run (another scene, another
/// response method). The poses are the recorded world poses: give the replay device no
/// translate/rotate/scale unless the new scene is placed differently.
#include <atomic>
#include <filesystem>
#include <vector>

#include "trocar/device/device.h"

namespace trocar {

/// Plays instrument `instrument`'s device poses from a recording (read whole at construction).
class ReplayDevice final : public Device {
 public:
  /// Throws trocar::FileError for an unreadable recording or one without ticks for the
  /// instrument. A recording cut short (killed session) plays up to its last complete block.
  ReplayDevice(const std::filesystem::path& recording, std::size_t instrument, Real max_force = 3.3,
               Real damping = 2.0);
  void open() override {}
  void close() override {}
  /// The last recorded sample at or before now_s (held after the end); velocity from the
  /// neighbouring samples.
  DeviceStatus read(double now_s, DeviceInput& input) override;
  void write(const DeviceOutput& output) override;
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override;

 private:
  struct Sample {
    double t;       ///< s since the session started
    Pose pose;      ///< world
    Real jaw;
  };
  std::vector<Sample> samples_;
  std::size_t cursor_ = 0;  ///< last index returned (reads go forward in time)
  DeviceSpecs specs_;
  std::atomic<std::uint64_t> reads_{0};
  std::atomic<std::uint64_t> forces_{0};
};

}  // namespace trocar
