#include "realtime_command.h"

#include "cli_support.h"
#include "task_report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "trocar/core/error.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"
#include "trocar/study/scene_driver.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

nlohmann::json histogram_json(const TimingHistogram& h) {
  return {{"median", h.median()}, {"p99", h.p99()}, {"max", h.max()}, {"mean", h.mean()}, {"count", h.count()}};
}

// One device's counters: what a driver does not count stays 0 (the scripted and replay drivers
// have one connection and never drop; only openigtlink sees malformed messages).
nlohmann::json device_json(const DeviceReport& d) {
  const DeviceCounters& c = d.counters;
  return {{"name", d.name},
          {"poses_accepted", c.samples},
          {"malformed", c.malformed},
          {"connections", c.connections},
          {"drops", c.drops},
          {"forces_sent", c.forces_sent},
          {"disconnects_seen", d.disconnects}};
}

}  // namespace

void run_realtime(const RealtimeOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_method_option(scene, o.method);
  const double duration = o.duration >= 0 ? o.duration : scene.duration;
  RuntimeSettings settings;
  settings.haptic_rate_hz = o.rate_hz;
  settings.lockstep = o.lockstep;
  settings.duration = duration;
  settings.physics_timestep = scene.timestep;
  settings.lock_memory = true;
  scene.settings.measure_penetration = o.metrics;
  const std::string scene_name = scene.name;
  const std::vector<DeviceSpec> devices = scene.devices;

  Simulation sim(std::move(scene.world), scene.settings);
  std::vector<RuntimeChannel> channels = make_channels(devices, sim.world());
  std::unique_ptr<RecordingWriter> recorder;
  if (!o.record.empty()) {
    recorder = std::make_unique<RecordingWriter>(o.record, session_header(o.scene, read_scene_text(o.scene), sim, settings));
  }
  Runtime runtime(sim, std::move(channels), settings, recorder.get());
  // The scene's task: evaluated after every physics step; device button 1 fires its tacker.
  std::unique_ptr<Procedure> procedure;
  if (scene.task) procedure = std::make_unique<Procedure>(*scene.task, sim.world(), scene.zones, scene.landmarks);
  runtime.set_procedure(procedure.get());
  const RuntimeReport r = runtime.run();
  if (recorder) finish_recording(*recorder, sim);
  for (const std::string& w : r.warnings) std::cerr << "trocar: warning: " << w << "\n";

  const PhysicsTimings& p = r.physics;
  nlohmann::json haptic = {
      {"mode", o.lockstep ? "lockstep" : "multirate"},
      {"rate_nominal_hz", o.rate_hz},
      {"rate_hz", r.rate_hz},
      {"deadline_miss_fraction", r.deadline_miss_fraction},
      {"jitter_us_p99", r.jitter_us_p99},
      {"period_us", histogram_json(r.period_us)},
      {"ticks", r.ticks},
      {"skipped_slots", r.skipped_slots},
      {"physics_rate_hz", r.physics_rate_hz},
      {"physics_steps", r.physics_steps},
      {"realtime_factor", r.wall_time > 0 ? r.sim_time / r.wall_time : 0},
      {"disconnects", r.disconnects},
      {"devices", [&] {
         nlohmann::json list = nlohmann::json::array();
         for (const DeviceReport& d : r.devices) list.push_back(device_json(d));
         return list;
       }()},
      {"recording_dropped", r.recording_dropped},
      {"timing_us",
       {{"haptic_tick", histogram_json(r.tick_us)},
        {"broad_phase", histogram_json(p.broad_phase)},
        {"narrow_phase", histogram_json(p.narrow_phase)},
        {"response", histogram_json(p.response)},
        {"deformation", histogram_json(p.deformation)},
        {"projection", histogram_json(p.projection)},
        {"step", histogram_json(p.step)},
        {"model", histogram_json(p.model)}}},
      {"warnings", r.warnings},
  };
  nlohmann::json report = {
      {"scene", scene_name},
      {"method", response_method_name(sim.settings().response.method)},
      {"steps", r.physics_steps},
      {"sim_time_s", r.sim_time},
      {"wall_time_s", r.wall_time},
      {"timing_us",
       {{"broad_phase", histogram_json(p.broad_phase)},
        {"narrow_phase", histogram_json(p.narrow_phase)},
        {"response", histogram_json(p.response)},
        {"deformation", histogram_json(p.deformation)},
        {"step", histogram_json(p.step)}}},
      {"stable", step_is_stable(sim.metrics(), tissue_mass(sim.world()))},
      {"state_hash", hash_hex(sim.state_hash())},
      {"haptic", haptic},
  };
  if (procedure) report["task"] = task_report(*procedure);
  if (!o.report.empty()) write_atomically(o.report, report.dump(2) + "\n");
  if (!o.quiet)
    std::printf("%s (real time, %s): %llu haptic ticks at %.1f Hz (nominal %.0f), deadline misses %.4f %%, jitter p99 "
                "%.1f us, tick p99 %.1f us; physics %llu steps at %.1f Hz, step median %.1f us; hash %s\n",
                scene_name.c_str(), o.lockstep ? "lock-step" : "multirate", (unsigned long long)r.ticks, r.rate_hz,
                o.rate_hz, 100 * r.deadline_miss_fraction, r.jitter_us_p99, r.tick_us.p99(),
                (unsigned long long)r.physics_steps, r.physics_rate_hz, p.step.median(),
                hash_hex(sim.state_hash()).c_str());
  if (!o.quiet)
    for (std::size_t i = 0; i < r.devices.size(); ++i) {
      const DeviceReport& d = r.devices[i];
      std::printf("  device %zu (%s): %llu poses accepted, %llu malformed, %llu connections, %llu drops\n", i,
                  d.name.c_str(), (unsigned long long)d.counters.samples, (unsigned long long)d.counters.malformed,
                  (unsigned long long)d.counters.connections, (unsigned long long)d.counters.drops);
    }
  if (procedure && !o.quiet) print_task(*procedure);
}

}  // namespace trocar::cli
