#include "trocar/device/port_device.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/Geometry>

namespace trocar {
namespace {

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

PortKinematics::PortKinematics(const Pose& start, const Vec3& shaft, const Vec3& pivot, const Vec3& up)
    : start_(start), shaft_(shaft.normalized()), pivot_(pivot) {
  depth0_ = std::max<Real>(0, (pivot_ - start_.translation).dot(shaft_));
  up_ = orthogonal_towards(shaft_, up);
  side_ = shaft_.cross(up_);
}

Pose PortKinematics::pose(const PortCommand& c) const {
  // Roll about the shaft, then yaw and pitch about the port: R = R_yaw · R_pitch · R_roll, all
  // through the pivot; insertion slides the pose origin along the (rotated) shaft. The tip stays
  // at least 5 mm inside the port.
  const Eigen::Quaterniond rotation = Eigen::AngleAxisd(c.yaw, up_) * Eigen::AngleAxisd(c.pitch, side_) *
                                      Eigen::AngleAxisd(c.roll, shaft_);
  const Real depth = std::max(c.depth, 0.005 - depth0_);
  Pose p;
  p.rotation = (rotation * start_.rotation).normalized();
  p.translation = pivot_ + rotation * (start_.translation - pivot_ - depth * shaft_);
  return p;
}

Vec3 default_port(const Pose& start, const Vec3& top_vertex_local, Real fraction) {
  const Vec3 top = start.apply(top_vertex_local);
  return start.translation + fraction * (top - start.translation);
}

PortDevice::PortDevice(const PortKinematics& kinematics) : kinematics_(kinematics) {
  specs_.name = "mouse (port pivot)";
  specs_.max_force = 0;  // renders no force
  specs_.native_rate_hz = 0;
  specs_.damping = 2.0;  // stands for a desktop device, so the default coupling passes the passivity check
  set(PortCommand{});
}

void PortDevice::open() { open_.store(true, std::memory_order_release); }

void PortDevice::set(const PortCommand& command) {
  command_ = command;
  DeviceInput in;
  in.pose = kinematics_.pose(command);
  in.jaw = std::clamp<Real>(command.jaw, 0, 1);
  in.buttons = command.buttons;
  in.timestamp_ns = steady_ns();
  in.sequence = last_.sequence + 1;
  const double dt = last_.sequence ? double(in.timestamp_ns - last_.timestamp_ns) * 1e-9 : 0.0;
  // Finite-difference velocity over the UI's event interval (zero for the first sample or a
  // burst within 1 ms), for the coupling's damper.
  in.velocity = dt > 1e-3 ? Vec3((in.pose.translation - last_.pose.translation) / dt) : Vec3::Zero();
  last_ = in;
  input_.publish(in);
  samples_.fetch_add(1, std::memory_order_relaxed);
}

DeviceStatus PortDevice::read(double, DeviceInput& input) {
  if (!open_.load(std::memory_order_acquire)) return DeviceStatus::kDisconnected;
  input_.read(input);
  // The UI sends samples only while the user moves: an old sample is a resting hand.
  if (steady_ns() - input.timestamp_ns > 30000000) input.velocity = Vec3::Zero();
  return DeviceStatus::kConnected;
}

void PortDevice::write(const DeviceOutput&) {}

DeviceCounters PortDevice::counters() const {
  DeviceCounters c;
  c.samples = samples_.load(std::memory_order_relaxed);
  c.connections = 1;
  return c;
}

}  // namespace trocar
