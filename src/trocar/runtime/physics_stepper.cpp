#include "trocar/runtime/physics_stepper.h"

#include <algorithm>

#include "trocar/core/timer.h"

namespace trocar {

const StepMetrics& apply_recorded_step(Simulation& sim, const StepRecord& record, ActionHandler* handler) {
  for (std::size_t i = 0; i < record.instruments; ++i)
    if (record.instrument[i].actions != 0) apply_actions(sim, i, record.instrument[i].actions, handler);
  for (std::size_t i = 0; i < record.instruments; ++i) {
    const StepInstrument& s = record.instrument[i];
    if (s.mode == 1) sim.command_instrument(i, from_words(s.pose), s.jaw);
    else if (s.mode == 2) sim.place_instrument(i, from_words(s.pose), s.jaw);
  }
  return sim.step(record.dt);
}

PhysicsStepper::PhysicsStepper(Simulation& sim, Real stiffness_prior, Real force_filter)
    : sim_(sim), instruments_(std::min(sim.world().instruments.size(), kMaxRuntimeInstruments)),
      force_filter_(force_filter) {
  for (auto& e : estimators_) e = ContactStiffnessEstimator(stiffness_prior);
  for (auto& f : filtered_force_) f = Vec3::Zero();
}

const ContactModelSet& PhysicsStepper::step(const InstrumentCommandSet& commands, Real dt, std::int64_t now_ns,
                                            StepRecord& record) {
  record = StepRecord{};
  record.dt = dt;
  record.instruments = static_cast<std::uint32_t>(instruments_);
  for (std::size_t i = 0; i < instruments_; ++i) {
    const InstrumentCommand& c = commands.instruments[i];
    record.instrument[i].actions = button_actions(held_actions_[i], c.actions);
    held_actions_[i] = c.actions;
  }
  for (std::size_t i = 0; i < instruments_; ++i) {
    const InstrumentCommand& c = commands.instruments[i];
    if (!c.active) continue;  // keyframes until the device's first sample
    // A device drives its port: whichever instrument of the port is in the body (an exchange
    // pressed this step takes effect from the next).
    const std::size_t target = std::min(sim_.active_in_port(i), instruments_ - 1);
    StepInstrument& s = record.instrument[target];
    s.mode = placed_[target] ? 1U : 2U;
    placed_[target] = true;
    s.pose = to_words(c.pose);
    s.jaw = c.jaw;
  }
  const StepMetrics& m = apply_recorded_step(sim_, record, handler_);

  const Timer model_timer;
  for (std::size_t i = 0; i < instruments_; ++i) {
    const Vec3 force = sim_.instrument_metrics()[std::min(sim_.active_in_port(i), instruments_ - 1)].force;
    const Vec3 position = sim_.world().instruments[i].instrument.pose().translation;
    // First-order low-pass, exact for a held input: a = dt/(τ + dt) (backward Euler of τ ḟ = F − f).
    const Real a = force_filter_ > 0 ? dt / (force_filter_ + dt) : 1;
    filtered_force_[i] += a * (force - filtered_force_[i]);
    if (force.squaredNorm() == 0 && filtered_force_[i].norm() < 1e-3) filtered_force_[i].setZero();
    models_.instruments[i] = estimators_[i].update(position, filtered_force_[i]);
    record.instrument[i].force = {force.x(), force.y(), force.z()};
  }
  models_.step = m.step_index;
  models_.timestamp_ns = now_ns;
  const double model_us = model_timer.microseconds();

  record.step = m.step_index;
  record.contacts = m.contacts;
  const StageTimings& t = m.timings;
  record.timing_us = {float(t.broad_phase), float(t.narrow_phase), float(t.response), float(t.deformation),
                      float(t.projection), float(t.step), float(model_us)};
  timings_.broad_phase.add(t.broad_phase);
  timings_.narrow_phase.add(t.narrow_phase);
  timings_.response.add(t.response);
  timings_.deformation.add(t.deformation);
  timings_.projection.add(t.projection);
  timings_.step.add(t.step);
  timings_.model.add(model_us);
  return models_;
}

}  // namespace trocar
