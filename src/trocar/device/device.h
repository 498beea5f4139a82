#pragma once
/// The device layer (docs/devices.md, docs/architecture.md "Layout"): what moves an instrument and
/// renders its force. A driver reports poses in metres in its own frame; the runtime maps that
/// frame into the world (runtime/device_mapping.h) and couples the instrument to it.
#include <cstdint>
#include <memory>
#include <string>

#include "trocar/core/pose.h"
#include "trocar/core/types.h"

namespace trocar {

/// Whether a device is feeding fresh samples.
enum class DeviceStatus : std::uint8_t {
  kConnected,     ///< samples arrive
  kStale,         ///< connected, but no sample for longer than the driver's stale limit
  kDisconnected,  ///< no connection (never opened, closed, or the peer went away)
};

/// "connected", "stale" or "disconnected".
const char* to_string(DeviceStatus status);

/// What a device can do (the values the coupling's passivity check and the force clamp use).
struct DeviceSpecs {
  std::string name;              ///< driver and model, e.g. "openigtlink :18944"
  Real max_force = 0;            ///< largest force it renders (N); 0 = renders no force
  Real max_torque = 0;           ///< largest torque it renders (N·m); 0 = none
  Vec3 workspace = Vec3::Zero(); ///< extent of its workspace box in its frame (m)
  Real native_rate_hz = 0;       ///< rate at which it produces samples (Hz); 0 = on demand
  /// The device's own viscous damping b (N·s/m), the b of the passivity bound K ≤ 2(b − B)/T
  /// (Colgate & Schenkel 1997). A value from the device's data sheet or identification.
  Real damping = 0;
};

/// One sample from the device (plain data of standard layout: it goes through a Seqlock).
struct DeviceInput {
  Pose pose;                               ///< device frame (m)
  Vec3 velocity = Vec3::Zero();            ///< linear velocity (m/s), device frame
  Vec3 angular_velocity = Vec3::Zero();    ///< rad/s, device frame
  Real jaw = 0;                            ///< jaw closure 0 (open) … 1 (closed)
  std::uint32_t buttons = 0;               ///< bit i = button i pressed
  std::int64_t timestamp_ns = 0;           ///< steady-clock time the sample was taken (ns)
  std::uint64_t sequence = 0;              ///< samples received so far (1 = the first)
};

/// What the haptic loop sends to the device, in the device frame.
struct DeviceOutput {
  Vec3 force = Vec3::Zero();    ///< N
  Vec3 torque = Vec3::Zero();   ///< N·m
  std::int64_t timestamp_ns = 0;  ///< steady-clock time of the tick that computed it (ns)
};

/// Counters every driver keeps (read from any thread).
struct DeviceCounters {
  std::uint64_t samples = 0;      ///< samples accepted
  std::uint64_t malformed = 0;    ///< messages dropped as malformed (size, type, CRC, NaN …)
  std::uint64_t connections = 0;  ///< connections accepted so far (a reconnect adds one)
  std::uint64_t drops = 0;        ///< connections lost: the peer left or reset, or was cut off
  std::uint64_t forces_sent = 0;  ///< force messages sent
};

/// A device driver. read() and write() are called from the haptic tick: they must not block,
/// allocate, lock, throw or log. open() and close() are called outside it and may throw
/// trocar::Error with a clear message.
class Device {
 public:
  virtual ~Device() = default;
  /// Starts the driver (opens a port, a socket, a file). Throws trocar::Error on failure.
  virtual void open() = 0;
  /// Stops it; idempotent.
  virtual void close() = 0;
  /// The newest sample at time now_s (s since the runtime started; the scripted and replay
  /// drivers sample their motion at it, live drivers return their latest sample). Leaves
  /// `input` unchanged when the device has never produced a sample. Returns the status.
  virtual DeviceStatus read(double now_s, DeviceInput& input) = 0;
  /// Sends a force (dropped by drivers without force output).
  virtual void write(const DeviceOutput& output) = 0;
  /// What the device can do.
  virtual const DeviceSpecs& specs() const = 0;
  /// Counters (thread-safe).
  virtual DeviceCounters counters() const = 0;
};

}  // namespace trocar
