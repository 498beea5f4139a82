#include "trocar/runtime/runtime.h"

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <thread>

#include "trocar/core/error.h"
#include "trocar/core/seqlock.h"
#include "trocar/runtime/realtime.h"

namespace trocar {

struct Runtime::Shared {
  Seqlock<ContactModelSet> models;          // physics → haptic
  Seqlock<InstrumentCommandSet> commands;   // haptic → physics
  std::atomic<bool> stop{false};
  std::vector<std::string> haptic_warnings;   // written by the haptic thread outside its ticks
  std::vector<std::string> physics_warnings;  // written by the physics thread before its loop
  // Haptic-thread state (only it touches these).
  ContactModelSet tick_models;
  InstrumentCommandSet tick_commands;
  StepRecord lockstep_record;
  std::uint64_t late_ticks = 0;
  std::uint64_t skipped_slots = 0;
};

Runtime::Runtime(Simulation& sim, std::vector<RuntimeChannel> channels, const RuntimeSettings& settings,
                 RecordingWriter* recorder)
    : sim_(sim), channels_(std::move(channels)), settings_(settings),
      clock_(settings.clock ? *settings.clock : steady_clock()), recorder_(recorder),
      stepper_(sim, settings.stiffness_prior), shared_(std::make_unique<Shared>()) {
  const std::size_t n = sim.world().instruments.size();
  if (n > kMaxRuntimeInstruments)
    throw Error("the real-time runtime drives at most " + std::to_string(kMaxRuntimeInstruments) +
                " instruments; the scene has " + std::to_string(n));
  if (channels_.size() != n)
    throw Error("the runtime needs one device per instrument: " + std::to_string(channels_.size()) + " for " +
                std::to_string(n));
  if (!(settings_.haptic_rate_hz > 0 && settings_.haptic_rate_hz <= 100000))
    throw Error("haptic rate " + std::to_string(settings_.haptic_rate_hz) + " Hz: must be in (0, 100000]");
  if (!settings_.lockstep && !(settings_.physics_timestep > 0)) throw Error("physics timestep must be > 0");
  const double period = 1.0 / settings_.haptic_rate_hz;
  for (RuntimeChannel& c : channels_) {
    if (!c.device) throw Error(c.where + ": no device");
    check_coupling_passivity(c.coupling, c.device->specs().damping, period, c.where + ".coupling");
    if (c.device->specs().max_force > 0) c.shaping.max_force = std::min(c.shaping.max_force, c.device->specs().max_force);
    else c.shaping.max_force = 0;  // a device without force output (spacemouse) is sent none
  }
  haptic_.reserve(channels_.size());
  ModelHandover handover = settings_.handover;
  if (settings_.lockstep) handover.blend_ticks = 1;  // a fresh model every tick: nothing to blend
  for (RuntimeChannel& c : channels_) haptic_.emplace_back(*c.device, c.mapping, c.coupling, c.shaping, handover);
  period_ns_ = static_cast<std::int64_t>(std::llround(1e9 * period));
}

Runtime::~Runtime() {
  for (RuntimeChannel& c : channels_)
    if (c.device) c.device->close();
}

void Runtime::haptic_tick(std::int64_t now_ns, double period_s, TickRecord& record) {
  Shared& s = *shared_;
  const double now_s = double(now_ns - start_ns_) * 1e-9;
  if (!settings_.lockstep) s.models.read(s.tick_models);
  for (HapticChannel& h : haptic_) h.sense(now_s);
  if (settings_.lockstep) {
    for (std::size_t i = 0; i < haptic_.size(); ++i) s.tick_commands.instruments[i] = haptic_[i].command();
    s.tick_models = stepper_.step(s.tick_commands, period_s, now_ns, s.lockstep_record);
    if (procedure_) procedure_->update(sim_);
    s.lockstep_record.time_ns = now_ns - start_ns_;
    if (recorder_) recorder_->push_step(s.lockstep_record);
  }
  record.instruments = static_cast<std::uint32_t>(haptic_.size());
  for (std::size_t i = 0; i < haptic_.size(); ++i) {
    const double age = s.tick_models.step ? double(now_ns - s.tick_models.timestamp_ns) * 1e-9 : 0.0;
    haptic_[i].actuate(s.tick_models.instruments[i], s.tick_models.step, age, period_s, record.instrument[i]);
  }
  if (!settings_.lockstep) {
    for (std::size_t i = 0; i < haptic_.size(); ++i) s.tick_commands.instruments[i] = haptic_[i].command();
    ++s.tick_commands.tick;
    s.commands.publish(s.tick_commands);
  }
}

void Runtime::haptic_thread() {
  Shared& s = *shared_;
  if (settings_.realtime_scheduling) {
    const std::string w = make_current_thread_realtime(49, settings_.haptic_cpu);
    if (!w.empty()) s.haptic_warnings.push_back("haptic thread: " + w);
  }
  const double period_s = double(period_ns_) * 1e-9;
  const std::int64_t end_ns = settings_.duration > 0
                                  ? start_ns_ + static_cast<std::int64_t>(std::llround(settings_.duration * 1e9))
                                  : INT64_MAX;
  std::int64_t next = start_ns_;
  std::int64_t previous = 0;
  TickRecord record;
  std::uint64_t tick = 0;
  const std::int64_t spin = std::min(settings_.spin_ns, period_ns_ / 2);
  while (next < end_ns && !stop_requested_.load(std::memory_order_relaxed)) {
    clock_.wait_until(next, spin);
    const std::int64_t t0 = clock_.now_ns();
    if (double(t0 - next) > 0.1 * double(period_ns_)) ++s.late_ticks;
    if (previous != 0) {
      const double period_us = double(t0 - previous) * 1e-3;
      report_.period_us.add(period_us);
      report_.jitter_us.add(std::abs(period_us - double(period_ns_) * 1e-3));
      record.period_us = static_cast<float>(period_us);
    }
    previous = t0;
    haptic_tick(t0, period_s, record);
    const std::int64_t t1 = clock_.now_ns();
    const double compute_us = double(t1 - t0) * 1e-3;
    report_.tick_us.add(compute_us);
    record.tick = tick++;
    record.time_ns = t0 - start_ns_;
    record.compute_us = static_cast<float>(compute_us);
    if (recorder_) recorder_->push_tick(record);
    next += period_ns_;
    // Behind by a whole period (a stall): skip the slots already past instead of a burst of
    // back-to-back ticks, and count them as missed (those of the run: ticks + skipped = slots).
    while (next + period_ns_ < t1) {
      if (next < end_ns) ++s.skipped_slots;  // the slot passed over is `next`, not the one after it
      next += period_ns_;
    }
    live_.ticks.store(tick, std::memory_order_relaxed);
    live_.late_ticks.store(s.late_ticks + s.skipped_slots, std::memory_order_relaxed);
  }
  report_.ticks = tick;
  s.stop.store(true, std::memory_order_release);
}

void Runtime::physics_thread() {
  Shared& s = *shared_;
  if (settings_.realtime_scheduling) {
    const std::string w = make_current_thread_realtime(48, settings_.physics_cpu);
    if (!w.empty()) s.physics_warnings.push_back("physics thread: " + w);
  }
  const Real dt = settings_.physics_timestep;
  const auto step_ns = static_cast<std::int64_t>(std::llround(dt * 1e9));
  InstrumentCommandSet commands;
  StepRecord record;
  ContactModelSet models;
  std::int64_t next = start_ns_;
  const auto view_ns = settings_.view_rate_hz > 0 ? static_cast<std::int64_t>(1e9 / settings_.view_rate_hz) : 0;
  std::int64_t next_view = start_ns_;
  clock_.wait_until(start_ns_, 0);  // start with the haptic thread, not before
  while (!s.stop.load(std::memory_order_acquire)) {
    const bool hold = paused_.load(std::memory_order_acquire) && step_requests_.load(std::memory_order_acquire) == 0;
    if (hold) {  // paused: the haptic loop keeps rendering the last models
      next += step_ns;
      clock_.wait_until(next, 0);
      continue;
    }
    if (paused_.load(std::memory_order_relaxed)) step_requests_.fetch_sub(1, std::memory_order_acq_rel);
    s.commands.read(commands);
    models = stepper_.step(commands, dt, 0, record);
    if (procedure_) procedure_->update(sim_);
    live_.physics_steps.fetch_add(1, std::memory_order_relaxed);
    if (view_ns > 0 && clock_.now_ns() >= next_view) {
      capture_view(sim_, views_.back());
      views_.publish();
      if (procedure_) {  // the panel's text: at the view rate, never inside the step
        task_views_.back() = procedure_->view();
        task_views_.publish();
      }
      next_view += view_ns;
      if (next_view < clock_.now_ns()) next_view = clock_.now_ns() + view_ns;
    }
    const std::int64_t now = clock_.now_ns();
    models.timestamp_ns = now;
    s.models.publish(models);
    record.time_ns = now - start_ns_;
    if (recorder_) recorder_->push_step(record);
    next += step_ns;
    if (now < next) clock_.wait_until(next, 0);
    else if (now > next + 5 * step_ns) next = now;  // fallen behind: run on, don't burst
  }
}

void Runtime::set_procedure(Procedure* procedure) {
  procedure_ = procedure;
  stepper_.set_action_handler(procedure);
}

RuntimeReport Runtime::run() {
  for (RuntimeChannel& c : channels_) c.device->open();
  if (settings_.lock_memory) {
    const std::string w = lock_memory();
    if (!w.empty()) report_.warnings.push_back(w);
  }
  start_ns_ = clock_.now_ns() + 20000000;  // 20 ms for the threads to start and take their CPUs
  const std::uint64_t steps_before = sim_.metrics().step_index;
  const double sim_before = sim_.time();
  if (settings_.view_rate_hz > 0 && !settings_.lockstep)
    for (ViewSnapshot& v : views_.slots()) {  // sized before the threads start; captures then reuse the storage
      capture_view(sim_, v);
      v.contacts.reserve(4096);
    }
  live_.started_ns.store(start_ns_, std::memory_order_relaxed);
  live_.running.store(true, std::memory_order_release);
  std::thread physics;
  if (!settings_.lockstep) physics = std::thread([this] { physics_thread(); });
  std::thread haptic([this] { haptic_thread(); });
  haptic.join();
  if (physics.joinable()) physics.join();
  const std::int64_t end = clock_.now_ns();
  live_.running.store(false, std::memory_order_release);
  for (RuntimeChannel& c : channels_) c.device->close();

  Shared& s = *shared_;
  RuntimeReport& r = report_;
  r.wall_time = double(end - start_ns_) * 1e-9;
  r.rate_hz = r.wall_time > 0 ? double(r.ticks) / r.wall_time : 0;
  r.skipped_slots = s.skipped_slots;
  const double slots = double(r.ticks + s.skipped_slots);
  r.deadline_miss_fraction = slots > 0 ? double(s.late_ticks + s.skipped_slots) / slots : 0;
  r.jitter_us_p99 = r.jitter_us.p99();
  r.physics_steps = sim_.metrics().step_index - steps_before;
  r.physics_rate_hz = r.wall_time > 0 ? double(r.physics_steps) / r.wall_time : 0;
  r.sim_time = sim_.time() - sim_before;
  r.physics = stepper_.timings();
  for (const std::string& w : s.haptic_warnings) r.warnings.push_back(w);
  for (const std::string& w : s.physics_warnings) r.warnings.push_back(w);
  for (std::size_t i = 0; i < haptic_.size(); ++i) {
    r.devices.push_back({channels_[i].device->specs().name, channels_[i].device->counters(), haptic_[i].disconnects()});
    r.disconnects += haptic_[i].disconnects();
    if (haptic_[i].disconnects() > 0)
      r.warnings.push_back("instrument " + std::to_string(i) + ": device " + channels_[i].device->specs().name +
                           " dropped " + std::to_string(haptic_[i].disconnects()) +
                           " time(s); the instrument held its last pose and the force went to zero");
  }
  if (recorder_) {
    r.recording_dropped = recorder_->dropped();
    if (r.recording_dropped > 0)
      r.warnings.push_back("recording: " + std::to_string(r.recording_dropped) +
                           " records lost to a full ring (the disk is too slow); the recording cannot be replayed");
  }
  return r;
}

}  // namespace trocar
