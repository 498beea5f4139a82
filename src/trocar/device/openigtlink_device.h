#pragma once
/// The `openigtlink` driver: an OpenIGTLink server (Debian's libopenigtlink) that takes the
/// instrument's pose from a client and sends the rendered force back. This is how a PLUS server
/// with a real Touch/Phantom (PLUS's OpenIGTLink output), or 3D Slicer's OpenIGTLinkIF module,
/// drives trocar.
///
/// Messages in (one client at a time; a new client may connect after the last one left):
///  - TRANSFORM (48-byte body): a 4×4 homogeneous matrix; rotation part orthonormal (within
///    1e-3), translation in **millimetres** (the OpenIGTLink / PLUS / Slicer convention),
///    converted to metres.
///  - POSITION (28-byte body): position in millimetres and the full quaternion (x, y, z, w),
///    normalised on receipt (position-only and 3-element-quaternion bodies are malformed).
///  - Anything else, a body whose CRC or size is wrong, NaN/inf values, a non-orthonormal
///    rotation, a zero quaternion: dropped and counted (`DeviceCounters::malformed`); the
///    connection stays up. A header announcing a body over 1 MiB is garbage: counted, and the
///    connection is closed (the client may reconnect).
///  Protocol version 1 (what libopenigtlink 1.11 speaks): a version-2 message's body holds an
///  extended header and metadata, has another size, and is dropped as malformed.
/// Message out: after each accepted pose, a SENSOR message named `device_name` with 3 values,
/// the force (N) last given to write(), in the device frame, unit newton.
/// Status: disconnected without a client; stale when no pose came for `stale_after_s`, or the
/// current client has sent none yet (read() then gives the previous client's last pose).
#include <atomic>
#include <string>
#include <thread>

#include "trocar/core/seqlock.h"
#include "trocar/device/device.h"

namespace trocar {

/// Settings of the openigtlink driver (scene `instruments[i].device`).
struct OpenIgtLinkSettings {
  int port = 18944;                     ///< TCP port; 0 = any free one (port() tells which)
  std::string device_name = "trocar";   ///< name of the SENSOR messages sent back
  double stale_after_s = 0.1;           ///< s without a pose before the status is stale
  Real max_force = 3.3;                 ///< N, the device behind the client
  Real damping = 2.0;                   ///< N·s/m, its b (passivity bound)
  Vec3 workspace = Vec3(0.16, 0.12, 0.07);  ///< m
};

/// OpenIGTLink server driver. read() and write() touch only Seqlocks and atomics.
class OpenIgtLinkDevice final : public Device {
 public:
  explicit OpenIgtLinkDevice(const OpenIgtLinkSettings& settings);
  ~OpenIgtLinkDevice() override;
  /// Binds the port and starts the socket thread; throws trocar::Error if the port is taken.
  void open() override;
  void close() override;
  DeviceStatus read(double now_s, DeviceInput& input) override;
  void write(const DeviceOutput& output) override;
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override;
  int port() const { return bound_port_; }  ///< the port bound by open()

 private:
  void serve();
  OpenIgtLinkSettings settings_;
  DeviceSpecs specs_;
  Seqlock<DeviceInput> sample_;
  Seqlock<DeviceOutput> force_;
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> connect_sequence_{0};  // samples before the current client came
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> samples_{0}, malformed_{0}, connections_{0}, forces_sent_{0};
  int bound_port_ = 0;
  struct Sockets;
  Sockets* sockets_ = nullptr;
  std::thread thread_;
};

}  // namespace trocar
