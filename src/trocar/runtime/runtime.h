#pragma once
/// The real-time runtime around Simulation::step (docs/runtime.md, docs/architecture.md "The
/// real-time runtime"): a haptic thread at 1–10 kHz renders force from the local contact models
/// while a physics thread steps the simulation at its own rate (multirate), or physics runs inside
/// the haptic tick (lock-step). Threads exchange one consistent struct per publish through
/// Seqlocks; a recorder drains both into a file.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "trocar/core/triple_buffer.h"
#include "trocar/device/device.h"
#include "trocar/procedure/procedure.h"
#include "trocar/procedure/task_view.h"
#include "trocar/runtime/clock.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/histogram.h"
#include "trocar/runtime/physics_stepper.h"
#include "trocar/runtime/recording.h"
#include "trocar/sim/simulation.h"
#include "trocar/sim/view_snapshot.h"

namespace trocar {

/// How the runtime runs (CLI `trocar run --realtime`).
struct RuntimeSettings {
  Real haptic_rate_hz = 1000;   ///< 1, 4 or 10 kHz in practice
  bool lockstep = false;        ///< physics inside the haptic tick, dt = the haptic period
  Real duration = 1;            ///< s to run on the clock (wall time by default); ≤ 0 = until request_stop()
  Real physics_timestep = 1e-3; ///< s per physics step (multirate; the scene's timestep)
  bool realtime_scheduling = true;  ///< try SCHED_FIFO and CPU pinning (warn when refused)
  bool lock_memory = false;     ///< mlockall before starting
  int haptic_cpu = 1;           ///< CPU the haptic thread is pinned to (< 0: none)
  int physics_cpu = 0;          ///< CPU of the physics thread (< 0: none)
  /// The haptic wait polls the clock for its last spin_ns, at most half a period: a SCHED_FIFO
  /// thread that spins all the time is throttled by the kernel (sched_rt_runtime_us: 95 % of each
  /// second), which stalls it for tens of ms; sleeping half of each period stays well below.
  std::int64_t spin_ns = 200000;
  Real stiffness_prior = 500;   ///< N/m, contact stiffness before one is measured
  ModelHandover handover;       ///< blending and ageing of models
  /// Multirate: the physics thread publishes a ViewSnapshot to Runtime::views() at most this
  /// often (Hz; 0 = never), for a renderer on another thread.
  Real view_rate_hz = 0;
  /// The time the loops read and wait on (nullptr: the steady clock). It must outlive run().
  RuntimeClock* clock = nullptr;
};

/// What the runtime is doing now, readable from any thread while it runs (relaxed atomics the
/// loops store once per tick or step: no lock, no wait).
struct RuntimeLive {
  std::atomic<std::uint64_t> ticks{0};          ///< haptic ticks so far
  std::atomic<std::uint64_t> late_ticks{0};     ///< ticks > 10 % of a period late, plus skipped slots
  std::atomic<std::uint64_t> physics_steps{0};  ///< physics steps so far
  std::atomic<std::int64_t> started_ns{0};      ///< start of the loops on the runtime's clock
  std::atomic<bool> running{false};             ///< between the start and the join of the loops
};

/// One instrument's device and how it is coupled (index = the World's instrument index).
struct RuntimeChannel {
  std::unique_ptr<Device> device;  ///< the driver (opened by the runtime)
  DeviceMapping mapping;           ///< device frame → world
  CouplingSettings coupling;       ///< virtual coupling
  ForceShaping shaping;            ///< clamp, slew, safe start (max_force ≤ the device's)
  std::string where;               ///< e.g. "scene.json: instruments[0].device" (for errors)
};

/// One channel's device in the report: its counters at the end of the run.
struct DeviceReport {
  std::string name;              ///< DeviceSpecs::name, e.g. "openigtlink :18944"
  DeviceCounters counters;       ///< poses accepted, malformed, connections, drops, forces sent
  std::uint64_t disconnects = 0; ///< connected → not, as the haptic loop saw it
};

/// What a run measured (the report's `haptic` section, docs/runtime.md "Performance monitor").
struct RuntimeReport {
  std::uint64_t ticks = 0;                 ///< haptic ticks run
  std::uint64_t skipped_slots = 0;         ///< periods passed over after a stall (ticks + these = the run's periods)
  double rate_hz = 0;                      ///< achieved tick rate
  double deadline_miss_fraction = 0;       ///< ticks that started > 10 % of a period late
  double jitter_us_p99 = 0;                ///< p99 of |period − nominal| (µs)
  TimingHistogram period_us;               ///< tick-to-tick period
  TimingHistogram jitter_us;               ///< |period − nominal|
  TimingHistogram tick_us;                 ///< the tick's own compute
  std::uint64_t physics_steps = 0;         ///< steps run
  double physics_rate_hz = 0;              ///< achieved step rate
  double sim_time = 0;                     ///< simulated time reached (s)
  double wall_time = 0;                    ///< s
  PhysicsTimings physics;                  ///< per-module timing
  std::vector<std::string> warnings;       ///< scheduling refused, disconnects, dropped records
  std::vector<DeviceReport> devices;       ///< per channel
  std::uint64_t disconnects = 0;           ///< device drops seen by the haptic loop
  std::uint64_t recording_dropped = 0;     ///< records lost to full rings
};

/// Runs a Simulation on the runtime. The Simulation and the recorder must outlive run().
class Runtime {
 public:
  /// Checks every channel's coupling against the passivity bound at the haptic period (throws
  /// trocar::Error naming channel.where) and that there are at most kMaxRuntimeInstruments,
  /// one channel per instrument.
  Runtime(Simulation& sim, std::vector<RuntimeChannel> channels, const RuntimeSettings& settings,
          RecordingWriter* recorder = nullptr);
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;
  ~Runtime();

  /// Opens the devices, runs for settings.duration of the clock's time (or until
  /// request_stop()), joins, closes them.
  RuntimeReport run();

  /// Ends run() from another thread (the haptic loop ends after at most one more tick).
  void request_stop() { stop_requested_.store(true, std::memory_order_release); }
  /// Multirate: while paused the physics thread does not step (the haptic loop runs on the last
  /// contact models); step_once() then runs exactly one step.
  void set_paused(bool paused) { paused_.store(paused, std::memory_order_release); }
  bool paused() const { return paused_.load(std::memory_order_acquire); }  ///< see set_paused
  void step_once() { step_requests_.fetch_add(1, std::memory_order_acq_rel); }  ///< see set_paused
  /// The physics thread's view snapshots (settings.view_rate_hz); the reader calls update().
  TripleBuffer<ViewSnapshot>& views() { return views_; }
  /// The task the session trains (docs/procedure.md), or null: evaluated after every physics
  /// step, and the fire action (a device button, the viewer's key) fires its tacker. Set before
  /// run(); the procedure is the physics thread's while the runtime runs.
  void set_procedure(Procedure* procedure);
  /// The task's panel, published with each view snapshot while a procedure is set.
  TripleBuffer<TaskView>& task_views() { return task_views_; }
  /// Counters for a live display.
  const RuntimeLive& live() const { return live_; }

 private:
  void haptic_thread();
  void physics_thread();
  void haptic_tick(std::int64_t now_ns, double period_s, TickRecord& record);

  Simulation& sim_;
  std::vector<RuntimeChannel> channels_;
  std::vector<HapticChannel> haptic_;
  RuntimeSettings settings_;
  RuntimeClock& clock_;
  RecordingWriter* recorder_;
  PhysicsStepper stepper_;
  std::int64_t start_ns_ = 0;
  std::int64_t period_ns_ = 0;
  struct Shared;
  std::unique_ptr<Shared> shared_;
  RuntimeReport report_;
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> paused_{false};
  std::atomic<int> step_requests_{0};
  TripleBuffer<ViewSnapshot> views_;
  Procedure* procedure_ = nullptr;
  TripleBuffer<TaskView> task_views_;
  RuntimeLive live_;
};

}  // namespace trocar
