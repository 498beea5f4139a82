#include "trocar/device/device.h"

namespace trocar {

const char* to_string(DeviceStatus status) {
  switch (status) {
    case DeviceStatus::kConnected: return "connected";
    case DeviceStatus::kStale: return "stale";
    case DeviceStatus::kDisconnected: return "disconnected";
  }
  return "unknown";
}

}  // namespace trocar
