#include "trocar/device/spacemouse_device.h"

#include <spnav.h>

#include <chrono>
#include <algorithm>
#include <cmath>

#include "trocar/core/error.h"

namespace trocar {

double SpaceMouseIntegrator::scaled(double v) const {
  const double x = v / settings_.full_deflection;
  if (std::abs(x) <= settings_.dead_zone) return 0;
  return std::clamp(x, -1.0, 1.0);
}

void SpaceMouseIntegrator::advance(const SpaceMouseDeflection& d, double dt) {
  for (int k = 0; k < 3; ++k) {
    velocity_[k] = scaled(d.t[k]) * settings_.translation_speed;
    angular_[k] = scaled(d.r[k]) * settings_.rotation_speed;
  }
  pose_.translation += velocity_ * dt;
  const double angle = angular_.norm() * dt;
  if (angle > 0) pose_.rotation = (Quat(Eigen::AngleAxisd(angle, angular_.normalized())) * pose_.rotation).normalized();
}

SpaceMouseDevice::SpaceMouseDevice(const SpaceMouseSettings& settings) : settings_(settings) {
  specs_.name = "spacemouse";
  specs_.native_rate_hz = 1000;
}

SpaceMouseDevice::~SpaceMouseDevice() { close(); }

void SpaceMouseDevice::open() {
  if (open_) return;
  if (spnav_open() == -1)
    throw Error("spacemouse: cannot connect to the spacenavd daemon (is it installed and running?)");
  open_ = true;
  stop_ = false;
  thread_ = std::thread([this] { poll(); });
}

void SpaceMouseDevice::close() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (open_) spnav_close();
  open_ = false;
}

void SpaceMouseDevice::poll() {
  SpaceMouseIntegrator integrator(settings_);
  SpaceMouseDeflection d;
  std::uint32_t buttons = 0;
  std::uint64_t sequence = 0;
  const auto period = std::chrono::milliseconds(1);
  while (!stop_) {
    spnav_event e;
    while (spnav_poll_event(&e) != 0) {
      if (e.type == SPNAV_EVENT_MOTION) {
        d.t[0] = e.motion.x, d.t[1] = e.motion.y, d.t[2] = e.motion.z;
        d.r[0] = e.motion.rx, d.r[1] = e.motion.ry, d.r[2] = e.motion.rz;
      } else if (e.type == SPNAV_EVENT_BUTTON && e.button.bnum < 32) {
        const std::uint32_t bit = 1U << e.button.bnum;
        buttons = e.button.press ? (buttons | bit) : (buttons & ~bit);
      }
    }
    integrator.advance(d, 1e-3);
    DeviceInput in;
    in.pose = integrator.pose();
    in.velocity = integrator.velocity();
    in.angular_velocity = integrator.angular_velocity();
    in.buttons = buttons;
    in.jaw = (buttons & 1U) ? 1.0 : 0.0;  // button 0 closes the jaws
    in.timestamp_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::steady_clock::now().time_since_epoch()).count();
    in.sequence = ++sequence;
    sample_.publish(in);
    samples_.fetch_add(1);
    std::this_thread::sleep_for(period);
  }
}

DeviceStatus SpaceMouseDevice::read(double, DeviceInput& input) {
  if (!open_) return DeviceStatus::kDisconnected;
  DeviceInput s;
  sample_.read(s);
  if (s.sequence == 0) return DeviceStatus::kStale;
  input = s;
  return DeviceStatus::kConnected;
}

DeviceCounters SpaceMouseDevice::counters() const {
  DeviceCounters c;
  c.samples = samples_.load();
  c.connections = open_ ? 1 : 0;
  return c;
}

}  // namespace trocar
