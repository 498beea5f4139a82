#include "trocar/runtime/local_contact_model.h"

#include <algorithm>

namespace trocar {

Vec3 LocalContactModel::force_at(const Vec3& x) const {
  if (!in_contact) return Vec3::Zero();
  const Vec3 f = force0 + stiffness * normal * normal.dot(position0 - x);
  return normal.dot(f) > 0 ? f : Vec3::Zero();
}

LocalContactModel ContactStiffnessEstimator::update(const Vec3& position, const Vec3& force) {
  LocalContactModel m;
  m.position0 = position;
  m.force0 = force;
  const Real magnitude = force.norm();
  if (!(magnitude > 1e-9)) {
    reset();
    return m;
  }
  m.normal = force / magnitude;
  m.in_contact = true;
  // The anchor (last_*) moves only when a secant is taken, so a slow press (a few µm per step)
  // still gets one every few steps.
  bool move_anchor = !have_last_;
  if (have_last_) {
    // Secant along the normal: k = −Δ(n·F) / Δ(n·x); pressing in (n·Δx < 0) raises n·F.
    const Real dx = m.normal.dot(position - last_position_);
    const Real df = m.normal.dot(force - last_force_);
    if (std::abs(dx) > kMinMove) {
      const Real secant = std::clamp(-df / dx, Real(0), max_);
      k_ = k_ > 0 ? (1 - kSmoothing) * k_ + kSmoothing * secant : secant;
      move_anchor = true;
    }
  }
  m.stiffness = k_ > 0 ? k_ : prior_;
  if (move_anchor) {
    have_last_ = true;
    last_position_ = position;
    last_force_ = force;
  }
  return m;
}

void ContactStiffnessEstimator::reset() {
  k_ = 0;
  have_last_ = false;
}

}  // namespace trocar
