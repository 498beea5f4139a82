#include "trocar/runtime/coupling.h"

#include <cmath>
#include <sstream>

#include "trocar/core/error.h"

namespace trocar {

Real passivity_stiffness_bound(Real device_damping, Real coupling_damping, Real period_s) {
  return 2 * (device_damping - coupling_damping) / period_s;
}

void check_coupling_passivity(const CouplingSettings& coupling, Real device_damping, Real period_s,
                              const std::string& where) {
  const auto bad = [](Real v) { return !std::isfinite(v) || v < 0; };
  if (bad(coupling.stiffness)) throw Error(where + ".stiffness: must be a finite number >= 0");
  if (bad(coupling.damping)) throw Error(where + ".damping: must be a finite number >= 0");
  if (bad(device_damping)) throw Error(where + ": the device's damping must be a finite number >= 0");
  if (!(period_s > 0)) throw Error(where + ": the haptic period must be > 0");
  const Real bound = passivity_stiffness_bound(device_damping, coupling.damping, period_s);
  if (!(coupling.stiffness < bound)) {
    std::ostringstream m;
    m << where << ": stiffness " << coupling.stiffness << " N/m with damping " << coupling.damping
      << " N*s/m breaks the passivity bound K < 2(b - B)/T = 2(" << device_damping << " - " << coupling.damping
      << ")/" << period_s << " s = " << bound << " N/m (Colgate & Schenkel 1997; b is the device's damping)";
    throw Error(m.str());
  }
}

Vec3 coupled_force(const LocalContactModel& model, Real coupling_stiffness, const Vec3& device_position) {
  if (!model.in_contact) return Vec3::Zero();
  const Real k = model.stiffness;
  const Real big_k = coupling_stiffness;
  const Real series = big_k > 0 && k > 0 ? big_k * k / (big_k + k) : 0;
  const Vec3& n = model.normal;
  const Vec3 f = model.force0 + series * n * n.dot(model.position0 - device_position);
  return n.dot(f) > 0 ? f : Vec3::Zero();
}

Vec3 ForceShaper::shape(const Vec3& commanded, Real period_s) {
  Vec3 f = shaping_.force_scale * commanded;
  const Real magnitude = f.norm();
  if (!std::isfinite(magnitude)) f = Vec3::Zero();
  else if (magnitude > shaping_.max_force) f *= shaping_.max_force / magnitude;

  if (state_ == State::kWaiting) {
    if (f.norm() >= shaping_.engage_below) {
      last_ = Vec3::Zero();
      return last_;
    }
    state_ = State::kRamping;
    ramp_ = 0;
  }
  if (state_ == State::kRamping) {
    ramp_ += shaping_.ramp_time > 0 ? period_s / shaping_.ramp_time : 1;
    if (ramp_ >= 1) {
      ramp_ = 1;
      state_ = State::kOn;
    }
    f *= ramp_;
  }
  const Real max_step = shaping_.slew_rate * period_s;
  const Vec3 step = f - last_;
  const Real step_norm = step.norm();
  if (step_norm > max_step) f = last_ + step * (max_step / step_norm);
  last_ = f;
  return f;
}

void ForceShaper::disengage() {
  state_ = State::kWaiting;
  ramp_ = 0;
  last_ = Vec3::Zero();
}

}  // namespace trocar
