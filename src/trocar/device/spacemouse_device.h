#pragma once
/// The `spacemouse` driver: a 6-DOF 3D mouse (libspnav, through the spacenavd daemon) moves the
/// instrument by rate control — deflection is velocity — and renders no force.
#include <atomic>
#include <thread>

#include "trocar/core/seqlock.h"
#include "trocar/device/device.h"

namespace trocar {

/// How deflection becomes motion.
struct SpaceMouseSettings {
  double translation_speed = 0.05;  ///< m/s at full deflection
  double rotation_speed = 1.0;      ///< rad/s at full deflection
  double full_deflection = 350;     ///< spnav units of a full push
  double dead_zone = 0.05;          ///< fraction of full deflection ignored (sensor noise)
};

/// One deflection sample (spnav units): translation x, y, z and rotation about x, y, z.
struct SpaceMouseDeflection {
  double t[3] = {0, 0, 0};
  double r[3] = {0, 0, 0};
};

/// Integrates deflection into a pose (pure: the tests drive it without hardware).
class SpaceMouseIntegrator {
 public:
  explicit SpaceMouseIntegrator(const SpaceMouseSettings& settings = {}) : settings_(settings) {}
  /// Holds `d` for dt seconds: position += v dt, rotation = exp(ω dt) · rotation (ω in the
  /// world frame), each axis past the dead zone, linear in deflection.
  void advance(const SpaceMouseDeflection& d, double dt);
  const Pose& pose() const { return pose_; }          ///< device frame (m)
  const Vec3& velocity() const { return velocity_; }  ///< m/s
  const Vec3& angular_velocity() const { return angular_; }  ///< rad/s

 private:
  double scaled(double v) const;
  SpaceMouseSettings settings_;
  Pose pose_;
  Vec3 velocity_ = Vec3::Zero();
  Vec3 angular_ = Vec3::Zero();
};

/// Reads spnav events on a thread and integrates them at 1 kHz.
class SpaceMouseDevice final : public Device {
 public:
  explicit SpaceMouseDevice(const SpaceMouseSettings& settings);
  ~SpaceMouseDevice() override;
  /// Connects to spacenavd; throws trocar::Error when the daemon is not running.
  void open() override;
  void close() override;
  DeviceStatus read(double now_s, DeviceInput& input) override;
  void write(const DeviceOutput&) override {}  ///< no force output
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override;

 private:
  void poll();
  SpaceMouseSettings settings_;
  DeviceSpecs specs_;
  Seqlock<DeviceInput> sample_;
  std::atomic<bool> open_{false}, stop_{false};
  std::atomic<std::uint64_t> samples_{0};
  std::thread thread_;
};

}  // namespace trocar
