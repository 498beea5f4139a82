#pragma once
/// What the drivers that play a motion at the runtime's clock share (`scripted`: a scene's
/// keyframes; `replay`, in runtime/: a recorded session): always connected, one connection, never
/// a drop or a malformed message; reads and forces counted. A driver says only where the hand is.
#include <atomic>
#include <cstdint>
#include <string>

#include "trocar/device/device.h"

namespace trocar {

/// Base of the playback drivers.
class PlaybackDevice : public Device {
 public:
  void open() override {}
  void close() override {}
  /// The played pose, jaw and velocity at now_s; timestamp now_s, sequence = reads so far.
  DeviceStatus read(double now_s, DeviceInput& input) final;
  /// Counted, then dropped.
  void write(const DeviceOutput& output) final;
  const DeviceSpecs& specs() const final { return specs_; }
  DeviceCounters counters() const final;

 protected:
  /// `max_force` (N) and `damping` (N·s/m, the b of the passivity bound) describe the device it
  /// stands for.
  PlaybackDevice(std::string name, Real max_force, Real damping);

  /// Where the played hand is at now_s (s since the runtime started). No allocation.
  struct Played {
    Pose pose;
    Real jaw = 0;
    Vec3 velocity = Vec3::Zero();  ///< m/s
    std::uint32_t buttons = 0;     ///< DeviceInput::buttons
  };
  virtual Played play(double now_s) = 0;

  DeviceSpecs specs_;

 private:
  std::atomic<std::uint64_t> reads_{0};
  std::atomic<std::uint64_t> forces_{0};
};

}  // namespace trocar
