#pragma once
/// The physics side of the runtime: takes the haptic tick's commands, runs Simulation::step, and
/// builds the local contact models. Also what `trocar replay` runs, so that a replay takes the
/// very path the session took.
#include <array>
#include <cstdint>

#include "trocar/procedure/actions.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/histogram.h"
#include "trocar/runtime/local_contact_model.h"
#include "trocar/runtime/recording_format.h"
#include "trocar/sim/simulation.h"

namespace trocar {

/// The commands of one haptic tick, one per instrument (what physics reads through a Seqlock).
struct InstrumentCommandSet {
  std::array<InstrumentCommand, kMaxRuntimeInstruments> instruments{};  ///< by instrument index
  std::uint64_t tick = 0;  ///< haptic tick that published it
};

/// Per-module timing of the physics steps (µs), the seed's Fig. 5.4/5.5 modules.
struct PhysicsTimings {
  TimingHistogram broad_phase, narrow_phase, response, deformation, projection, step, model;
};

/// Applies a step record's actions (exchange; fire through `handler` when given), its instrument
/// modes (place, command, keyframes), and steps by its dt. The one function both the live
/// physics thread and replay use.
const StepMetrics& apply_recorded_step(Simulation& sim, const StepRecord& record, ActionHandler* handler = nullptr);

/// Steps a Simulation for the runtime (one thread at a time).
class PhysicsStepper {
 public:
  /// stiffness_prior: the contact stiffness (N/m) a model uses until one is measured.
  /// force_filter: time constant (s) of the low-pass on the step's instrument force before it
  /// enters the model (0 = none). The sdf constraint's force is an impulse per step (−Σ m Δx/dt²):
  /// its mean is the contact force, but step to step it swings by the tissue vertices' inertia,
  /// and a proxy that followed those swings would feed them back into the next step.
  PhysicsStepper(Simulation& sim, Real stiffness_prior, Real force_filter = kForceFilter);
  /// Who fires the tacker (the procedure); null: fire presses are recorded but do nothing.
  void set_action_handler(ActionHandler* handler) { handler_ = handler; }
  static constexpr Real kForceFilter = 0.005;  ///< s, the default low-pass time constant
  /// One step of dt seconds with `commands`; `now_ns` (steady clock) stamps the models. Fills
  /// `record` with what replay needs and the module timings. No allocation after the first.
  const ContactModelSet& step(const InstrumentCommandSet& commands, Real dt, std::int64_t now_ns, StepRecord& record);

  const ContactModelSet& models() const { return models_; }  ///< after the last step
  const PhysicsTimings& timings() const { return timings_; }  ///< so far

 private:
  Simulation& sim_;
  std::size_t instruments_;
  std::array<ContactStiffnessEstimator, kMaxRuntimeInstruments> estimators_;
  std::array<bool, kMaxRuntimeInstruments> placed_{};
  std::array<std::uint32_t, kMaxRuntimeInstruments> held_actions_{};  ///< per channel, last step's
  ActionHandler* handler_ = nullptr;
  std::array<Vec3, kMaxRuntimeInstruments> filtered_force_{};  ///< low-passed force (N)
  Real force_filter_;
  ContactModelSet models_;
  PhysicsTimings timings_;
};

}  // namespace trocar
