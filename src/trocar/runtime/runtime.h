#pragma once
/// The real-time runtime around Simulation::step (DESIGN.md §1): a haptic thread at 1–10 kHz
/// renders force from the local contact models while a physics thread steps the simulation at
/// its own rate (multirate), or physics runs inside the haptic tick (lock-step). Threads exchange
/// one consistent struct per publish through Seqlocks; a recorder drains both into a file.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "trocar/device/device.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/histogram.h"
#include "trocar/runtime/physics_stepper.h"
#include "trocar/runtime/recording.h"
#include "trocar/sim/simulation.h"

namespace trocar {

/// How the runtime runs (CLI `trocar run --realtime`).
struct RuntimeSettings {
  Real haptic_rate_hz = 1000;   ///< 1, 4 or 10 kHz in practice
  bool lockstep = false;        ///< physics inside the haptic tick, dt = the haptic period
  Real duration = 1;            ///< s of wall-clock time to run
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
};

/// One instrument's device and how it is coupled (index = the World's instrument index).
struct RuntimeChannel {
  std::unique_ptr<Device> device;  ///< the driver (opened by the runtime)
  DeviceMapping mapping;           ///< device frame → world
  CouplingSettings coupling;       ///< virtual coupling
  ForceShaping shaping;            ///< clamp, slew, safe start (max_force ≤ the device's)
  std::string where;               ///< e.g. "scene.json: instruments[0].device" (for errors)
};

/// What a run measured (DESIGN.md §6 `haptic` section).
struct RuntimeReport {
  std::uint64_t ticks = 0;                 ///< haptic ticks run
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
  std::vector<DeviceCounters> devices;     ///< per channel
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

  /// Opens the devices, runs for settings.duration of wall-clock time, joins, closes them.
  RuntimeReport run();

 private:
  void haptic_thread();
  void physics_thread();
  void haptic_tick(std::int64_t now_ns, double period_s, TickRecord& record);

  Simulation& sim_;
  std::vector<RuntimeChannel> channels_;
  std::vector<HapticChannel> haptic_;
  RuntimeSettings settings_;
  RecordingWriter* recorder_;
  PhysicsStepper stepper_;
  std::int64_t start_ns_ = 0;
  std::int64_t period_ns_ = 0;
  struct Shared;
  std::unique_ptr<Shared> shared_;
  RuntimeReport report_;
};

}  // namespace trocar
