#pragma once
/// The `openigtlink` driver: an OpenIGTLink server (Debian's libopenigtlink) that takes the
/// instrument's pose from a client and sends the rendered force back. This is how a PLUS server
/// with a real Touch/Phantom (PLUS's OpenIGTLink output), or 3D Slicer's OpenIGTLinkIF module,
/// drives trocar.
///
/// One client at a time, and the newest wins: a connection that arrives while a client is
/// connected replaces it (the old one is closed and counted as a drop). A restarted Slicer or
/// PLUS relay therefore always comes back, even when its old connection died without a word.
///
/// Messages in: TRANSFORM and POSITION, as openigtlink_parser.h describes (millimetres in,
/// metres out). A malformed message is dropped and counted (`DeviceCounters::malformed`); the
/// connection stays up. A header announcing a body over 1 MiB is garbage: counted, and the
/// connection is closed (the client may reconnect).
/// Message out: after each accepted pose, a SENSOR message named `device_name` with 3 values,
/// the force (N) last given to write(), in the device frame, unit newton. A client that does not
/// read them is not waited for: a reply that finds the previous one still unsent is skipped.
/// Status: disconnected without a client; stale when no pose came for `stale_after_s`, or the
/// current client has sent none yet (read() then gives the previous client's last pose).
#include <atomic>
#include <memory>
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
  struct Sockets;  // the listener, the client and the parser: the socket thread's own
  OpenIgtLinkSettings settings_;
  DeviceSpecs specs_;
  Seqlock<DeviceInput> sample_;
  Seqlock<DeviceOutput> force_;
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> connect_sequence_{0};  // samples before the current client came
  std::atomic<std::uint64_t> samples_{0}, malformed_{0}, connections_{0}, drops_{0}, forces_sent_{0};
  int bound_port_ = 0;
  std::unique_ptr<Sockets> sockets_;
  std::thread thread_;
};

}  // namespace trocar
