#pragma once
/// A laparoscopic instrument moved through its trocar port (driver "mouse"): the viewer's mouse
/// and keyboard set pitch, yaw, insertion depth, roll and jaw; the shaft pivots about the port,
/// the fulcrum a real abdominal wall imposes (4 DOF + jaw). The UI thread calls set(); the haptic
/// tick's read() takes the newest pose through a Seqlock, so neither waits for the other.
#include <atomic>

#include "trocar/core/pose.h"
#include "trocar/core/seqlock.h"
#include "trocar/device/device.h"

namespace trocar {

/// The port's degrees of freedom, relative to the starting pose.
struct PortCommand {
  Real yaw = 0;     ///< rad, about the port's up axis
  Real pitch = 0;   ///< rad, about the port's side axis (shaft × up)
  Real depth = 0;   ///< m, insertion beyond the start (+ = deeper)
  Real roll = 0;    ///< rad, about the shaft
  Real jaw = 0;     ///< closure 0 (open) … 1 (closed)
  /// Buttons held (DeviceInput::buttons: bit 1 fires the tacker, bit 2 exchanges the instrument
  /// in the port, bits 3, 5 and 7 are the pedal, suction and irrigation; docs/devices.md).
  std::uint32_t buttons = 0;
};

/// Pivot kinematics: a rigid rotation about the port point plus a slide along the shaft.
class PortKinematics {
 public:
  /// `start`: the instrument's pose at the start; `shaft`: unit world direction from the tip
  /// towards the handle at the start; `pivot`: the port (world, m) — on the shaft's line; `up`:
  /// the yaw axis hint (world).
  PortKinematics(const Pose& start, const Vec3& shaft, const Vec3& pivot, const Vec3& up = Vec3(0, 0, 1));
  /// The instrument pose for a command. Depth is limited so the tip never backs out past the port.
  Pose pose(const PortCommand& c) const;
  const Vec3& pivot() const { return pivot_; }  ///< world (m)
  Real start_depth() const { return depth0_; }  ///< tip's distance below the port at the start (m)

 private:
  Pose start_;
  Vec3 shaft_;   // tip → handle
  Vec3 pivot_;
  Vec3 up_, side_;
  Real depth0_ = 0;
};

/// The "mouse" driver: a PortKinematics fed from the UI thread.
class PortDevice final : public Device {
 public:
  explicit PortDevice(const PortKinematics& kinematics);
  void open() override;
  void close() override { open_.store(false, std::memory_order_release); }
  DeviceStatus read(double now_s, DeviceInput& input) override;
  void write(const DeviceOutput& output) override;
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override;

  /// From the UI thread: the new command (timestamped now). Never blocks.
  void set(const PortCommand& command);
  /// The last command set (UI thread only).
  const PortCommand& command() const { return command_; }
  const PortKinematics& kinematics() const { return kinematics_; }  ///< the pivot model

 private:
  PortKinematics kinematics_;
  DeviceSpecs specs_;
  PortCommand command_;        // UI thread
  DeviceInput last_;           // UI thread: for the finite-difference velocity
  Seqlock<DeviceInput> input_;
  std::atomic<bool> open_{false};
  std::atomic<std::uint64_t> samples_{0};
};

/// The port of an instrument whose scene gives none: on the shaft, `fraction` of the way from
/// the tip (pose origin) to the top vertex, at the instrument's starting pose.
Vec3 default_port(const Pose& start, const Vec3& top_vertex_local, Real fraction = 0.6);

}  // namespace trocar
