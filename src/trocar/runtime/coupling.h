#pragma once
/// Virtual coupling between the device and the simulated instrument (the proxy), and the force
/// shaping of the haptic tick: clamp, slew limit, safe start.
#include <string>

#include "trocar/core/types.h"
#include "trocar/runtime/local_contact_model.h"

namespace trocar {

/// The spring–damper between the device's position and the proxy's (scene key
/// `instruments[i].device.coupling`).
struct CouplingSettings {
  Real stiffness = 1000;  ///< K (N/m)
  Real damping = 0.5;     ///< B (N·s/m), on the proxy's velocity relative to the device's
};

/// The passivity bound of a sampled spring–damper rendered by a device with viscous damping b at
/// period T (Colgate & Schenkel, "Passivity of a class of sampled-data systems", 1997):
/// K·T/2 + B < b, i.e. K < 2(b − B)/T. Returns the largest K (N/m); ≤ 0 when B ≥ b.
Real passivity_stiffness_bound(Real device_damping, Real coupling_damping, Real period_s);

/// Throws trocar::Error naming `where` (e.g. "scene.json: instruments[0].device.coupling") when
/// K, B and the device's b at period T break the bound, or a value is negative or not finite.
void check_coupling_passivity(const CouplingSettings& coupling, Real device_damping, Real period_s,
                              const std::string& where);

/// The force rendered at device position x_d from one contact model, through the coupling.
/// Physics moves the simulated instrument to the device's pose at each step, so at x_d = x0 the
/// force is physics' own, F0. Between steps the model extrapolates along its normal with the
/// contact stiffness k in series with the coupling spring K,
///   k_s = K k / (K + k) ≤ K,   F(x_d) = F0 + k_s n nᵀ (x0 − x_d),
/// so however stiff the organ, the device never renders more than K (the passivity bound holds
/// for the stiffness it actually renders). Zero where the extrapolation would pull (n·F ≤ 0).
Vec3 coupled_force(const LocalContactModel& model, Real coupling_stiffness, const Vec3& device_position);

/// Per-tick force limits and the safe start (scene key `instruments[i].device`).
struct ForceShaping {
  Real force_scale = 1;     ///< the simulated force is multiplied by this before the clamp (a device
                            ///< weaker or stronger than the tissue model's forces)
  Real max_force = 3.3;     ///< N: |F| is clamped here (≤ the device's own maximum)
  Real slew_rate = 2000;    ///< N/s: largest change of the rendered force per second
  /// Safe start (as CHAI3D's tools do): after connecting, the force stays off until the
  /// commanded force is below this (N), then ramps in over ramp_time.
  Real engage_below = 0.2;
  Real ramp_time = 0.25;    ///< s
};

/// Applies ForceShaping tick by tick (one instance per instrument; allocation-free).
class ForceShaper {
 public:
  explicit ForceShaper(const ForceShaping& shaping = {}) : shaping_(shaping) {}
  /// The force to send this tick for the commanded force (N), at tick period T (s).
  Vec3 shape(const Vec3& commanded, Real period_s);
  /// Back to waiting for a small force (on disconnect), output zero.
  void disengage();
  bool engaged() const { return state_ != State::kWaiting; }  ///< force is (ramping) on
  const ForceShaping& settings() const { return shaping_; }   ///< the limits

 private:
  enum class State { kWaiting, kRamping, kOn };
  ForceShaping shaping_;
  State state_ = State::kWaiting;
  Real ramp_ = 0;              ///< 0…1 scale while ramping
  Vec3 last_ = Vec3::Zero();   ///< force sent last tick (N)
};

}  // namespace trocar
