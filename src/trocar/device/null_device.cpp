#include "trocar/device/null_device.h"

#include <cmath>

namespace trocar {

NullDevice::NullDevice(const Pose& pose) {
  specs_.name = "null";
  sample_.pose = pose;
  sample_.sequence = 1;
}

DeviceStatus NullDevice::read(double now_s, DeviceInput& input) {
  sample_.timestamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  input = sample_;
  ++counters_.samples;
  return DeviceStatus::kConnected;
}

void NullDevice::write(const DeviceOutput& /*output*/) { ++counters_.forces_sent; }

}  // namespace trocar
