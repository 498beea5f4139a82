#pragma once
/// The `null` driver: an instrument that stays where the scene put it and renders nothing.
#include "trocar/device/device.h"

namespace trocar {

/// Always connected, always at one pose (the device frame's origin unless given).
class NullDevice final : public Device {
 public:
  explicit NullDevice(const Pose& pose = Pose::identity());
  void open() override {}
  void close() override {}
  DeviceStatus read(double now_s, DeviceInput& input) override;
  void write(const DeviceOutput& output) override;
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override { return counters_; }

 private:
  DeviceSpecs specs_;
  DeviceInput sample_;
  DeviceCounters counters_;
};

}  // namespace trocar
