#pragma once
/// The `replay` driver: the device poses of a recorded session (its haptic ticks), played back
/// at the runtime's clock, so a recorded hand motion can drive a new run (another scene, another
/// response method). The poses are the recorded world poses: give the replay device no
/// translate/rotate/scale unless the new scene is placed differently.
#include <filesystem>
#include <vector>

#include "trocar/device/playback_device.h"

namespace trocar {

/// Plays instrument `instrument`'s device poses from a recording (read whole at construction).
class ReplayDevice final : public PlaybackDevice {
 public:
  /// Throws trocar::FileError for an unreadable recording or one without ticks for the
  /// instrument. A recording cut short (killed session) plays up to its last complete block.
  ReplayDevice(const std::filesystem::path& recording, std::size_t instrument, Real max_force = 3.3,
               Real damping = 2.0);

 private:
  struct Sample {
    double t;       ///< s since the session started
    Pose pose;      ///< world
    Real jaw;
  };
  std::vector<Sample> samples_;
  /// The last recorded sample at or before now_s (held after the end); velocity from the
  /// neighbouring samples.
  Played play(double now_s) override;
  std::size_t cursor_ = 0;  ///< last index returned (reads go forward in time)
};

}  // namespace trocar
