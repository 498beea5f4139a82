#pragma once
/// The `scripted` driver: a scene's keyframes played at the runtime's clock, as if a trainee's
/// hand followed them (the device side of today's `motion`). Forces sent to it are counted.
#include <atomic>

#include "trocar/device/device.h"
#include "trocar/sim/motion.h"

namespace trocar {

/// Samples a KeyframeMotion at read()'s time; velocity by central difference over 1 ms.
class ScriptedDevice final : public Device {
 public:
  /// `max_force` (N) and `damping` (N·s/m, the b of the passivity bound) describe the device it
  /// stands for; defaults as a Touch-class desktop device.
  explicit ScriptedDevice(KeyframeMotion motion, Real max_force = 3.3, Real damping = 2.0);
  void open() override {}
  void close() override {}
  DeviceStatus read(double now_s, DeviceInput& input) override;
  void write(const DeviceOutput& output) override;
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override;

 private:
  KeyframeMotion motion_;
  DeviceSpecs specs_;
  std::atomic<std::uint64_t> samples_{0};
  std::atomic<std::uint64_t> forces_{0};
};

}  // namespace trocar
