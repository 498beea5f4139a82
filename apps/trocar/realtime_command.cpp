#include "realtime_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "trocar/core/error.h"
#include "trocar/runtime/fidelity.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

nlohmann::json histogram_json(const TimingHistogram& h) {
  return {{"median", h.median()}, {"p99", h.p99()}, {"max", h.max()}, {"mean", h.mean()}, {"count", h.count()}};
}


}  // namespace

void run_realtime(const RealtimeOptions& o) {
  Scene scene = load_scene(o.scene);
  if (!o.method.empty()) {
    const auto method = parse_response_method(o.method);
    if (!method) throw Error("--method: unknown method \"" + o.method + "\" (known: sdf, obb, primitive, normal, project)");
    scene.settings.response.method = *method;
  }
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
      {"stable", sim.metrics().finite},
      {"state_hash", hash_hex(sim.state_hash())},
      {"haptic", haptic},
  };
  if (!o.report.empty()) {
    const fs::path tmp = o.report + ".tmp";
    {
      std::ofstream out(tmp);
      if (!out) throw Error(o.report + ": cannot write");
      out << report.dump(2) << "\n";
    }
    fs::rename(tmp, o.report);
  }
  if (!o.quiet)
    std::printf("%s (real time, %s): %llu haptic ticks at %.1f Hz (nominal %.0f), deadline misses %.4f %%, jitter p99 "
                "%.1f us, tick p99 %.1f us; physics %llu steps at %.1f Hz, step median %.1f us; hash %s\n",
                scene_name.c_str(), o.lockstep ? "lock-step" : "multirate", (unsigned long long)r.ticks, r.rate_hz,
                o.rate_hz, 100 * r.deadline_miss_fraction, r.jitter_us_p99, r.tick_us.p99(),
                (unsigned long long)r.physics_steps, r.physics_rate_hz, p.step.median(),
                hash_hex(sim.state_hash()).c_str());
}

namespace {

struct ReplayOptions {
  std::string recording;
  bool quiet = false;
};

struct PlotOptions {
  std::string recording;
  std::string out;
};

// The seed's Fig. 5.4/5.5: time per iteration of each module over the run.
void plot_timing(const PlotOptions& o) {
  const Recording rec = read_recording(o.recording, false);
  if (!rec.end)
    std::cerr << "trocar: warning: " << o.recording << ": byte " << rec.complete_bytes
              << ": the recording ends early (no end record); plotting its " << rec.steps.size() << " steps\n";
  const fs::path out = o.out.empty() ? fs::path(o.recording).parent_path() / "timing" : fs::path(o.out);
  fs::create_directories(out);
  {
    std::ofstream steps(out / "steps.dat");
    steps << "# step time_s";
    for (const char* n : kStepTimingNames) steps << " " << n << "_us";
    steps << "\n";
    for (const StepRecord& s : rec.steps) {
      steps << s.step << " " << double(s.time_ns) * 1e-9;
      for (float t : s.timing_us) steps << " " << t;
      steps << "\n";
    }
    std::ofstream ticks(out / "ticks.dat");
    ticks << "# tick time_s period_us compute_us\n";
    for (const TickRecord& t : rec.ticks)
      ticks << t.tick << " " << double(t.time_ns) * 1e-9 << " " << t.period_us << " " << t.compute_us << "\n";
  }
  std::ofstream gp(out / "timing.gp");
  const auto plot = [&](const char* terminal, const char* ext) {
    gp << "set terminal " << terminal << " size 1000,600\n"
       << "unset logscale y\nset xrange [0:*]\n"
       << "set output 'physics_timing." << ext << "'\n"
       << "set title 'Physics: time per step of each module (the seed, Fig. 5.4)'\n"
       << "set xlabel 'time (s)'\nset ylabel 'time per step (us)'\nset key outside right\nset grid\n"
       << "plot 'steps.dat' using 2:3 with lines title 'broad phase', '' using 2:4 with lines title 'narrow phase', "
          "'' using 2:5 with lines title 'response', '' using 2:6 with lines title 'deformation', "
          "'' using 2:8 with lines lw 2 title 'whole step'\n"
       << "set output 'haptic_timing." << ext << "'\n"
       << "set title 'Haptic loop: period and compute per tick (the seed, Fig. 5.5)'\n"
       << "set ylabel 'us (log scale)'\nset logscale y\n"
       << "plot 'ticks.dat' using 2:3 with lines title 'period', '' using 2:4 with lines title 'tick compute'\n";
  };
  plot("svg dynamic", "svg");
  plot("pngcairo", "png");
  gp.close();
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0)
    throw Error("gnuplot not found: the data and timing.gp are in " + out.string() + " (install gnuplot-nox)");
  const std::string cmd = "cd '" + out.string() + "' && gnuplot timing.gp";
  if (std::system(cmd.c_str()) != 0) throw Error("gnuplot failed on " + (out / "timing.gp").string());
  std::printf("plot timing: %zu steps, %zu ticks -> %s/{physics,haptic}_timing.{svg,png}\n", rec.steps.size(),
              rec.ticks.size(), out.string().c_str());
}

}  // namespace

void add_replay_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ReplayOptions>();
  CLI::App* cmd = app.add_subcommand("replay", "Redo a recorded real-time session in lock-step and check its state hash");
  cmd->add_option("recording", o->recording, "Session recording (trocar run --realtime --record)")->required();
  cmd->add_flag("--quiet,-q", o->quiet, "Print nothing but errors");
  cmd->callback([o, &exit_code]() {
    const ReplayResult r = replay_recording(o->recording);
    if (!o->quiet)
      std::printf("replay: %llu steps; state hash %s, recorded %s: %s\n", (unsigned long long)r.steps,
                  hash_hex(r.state_hash).c_str(), hash_hex(r.recorded_hash).c_str(),
                  r.matches() ? "identical" : "DIFFERENT");
    if (!r.matches()) exit_code = 3;
  });
}

void add_plot_command(CLI::App& app, int& /*exit_code*/) {
  auto o = std::make_shared<PlotOptions>();
  CLI::App* plot = app.add_subcommand("plot", "Plots of a recorded session");
  plot->require_subcommand(1);
  CLI::App* timing = plot->add_subcommand("timing", "Time per iteration of each module over the run (SVG and PNG)");
  timing->add_option("recording", o->recording, "Session recording")->required();
  timing->add_option("--out", o->out, "Output folder (default: timing/ beside the recording)");
  timing->callback([o]() { plot_timing(*o); });
}

namespace {

struct MultirateOptions {
  std::vector<std::string> scenes;
  double duration = 3;
  double rate_hz = 1000;
  std::string out = "multirate";
  bool emulate = false;
};

void print_fidelity(const std::string& scene, const char* how, const FidelityResult& r, std::ostream& md) {
  std::printf("%s (%s): %llu ticks, physics %.0f Hz; peak %.3f N, RMS error %.4f N = %.2f %% of peak (the physics themselves differ by %.2f %%); largest jump at "
              "a model arrival %.4f N = %.2f %% of the device's %.1f N (any tick: %.4f N; the reference's own: %.4f N)\n",
              scene.c_str(), how, (unsigned long long)r.ticks, r.physics_rate_hz, r.peak_force, r.rms_error,
              100 * r.rms_fraction, 100 * r.physics_rms_fraction, r.max_arrival_jump, 100 * r.max_arrival_jump / r.device_max_force,
              r.device_max_force, r.max_jump, r.reference_max_jump);
  md << "| " << scene << " | " << how << " | " << r.ticks << " | " << r.physics_rate_hz << " | " << r.peak_force
     << " | " << 100 * r.rms_fraction << " | " << 100 * r.physics_rms_fraction << " | "
     << 100 * r.max_arrival_jump / r.device_max_force << " | "
     << 100 * r.reference_max_jump / r.device_max_force << " |\n";
}

}  // namespace

void add_multirate_command(CLI::App& study) {
  auto o = std::make_shared<MultirateOptions>();
  CLI::App* cmd = study.add_subcommand(
      "multirate", "Force rendered at the haptic rate with physics at its own rate vs a lock-step reference");
  cmd->add_option("scenes", o->scenes, "Scene files")->required();
  cmd->add_option("--duration", o->duration, "Wall-clock seconds per run")->check(CLI::PositiveNumber);
  cmd->add_option("--haptic-rate", o->rate_hz, "Haptic rate (Hz)")->check(CLI::Range(1.0, 100000.0));
  cmd->add_option("--out", o->out, "Output folder (multirate.md and the recordings)");
  cmd->add_flag("--emulate", o->emulate, "Deterministic emulation (no threads: physics every tick, 1 tick late)");
  cmd->callback([o]() {
    fs::create_directories(o->out);
    std::ofstream md(fs::path(o->out) / "multirate.md");
    md << "| scene | run | ticks | physics Hz | peak force N | RMS error % of peak | physics apart % of peak | largest arrival jump % of device max | reference's own largest jump % |\n"
          "|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string& scene : o->scenes) {
      const std::string stem = fs::path(scene).stem().string();
      if (o->emulate) {
        const std::string text = read_scene_text(scene);
        EmulationOptions e;
        e.rate_hz = o->rate_hz;
        e.duration = o->duration;
        print_fidelity(stem, "emulated, 1 tick late", emulate_multirate(text, fs::path(scene).parent_path(), e), md);
        e.latency_ticks = 2;
        print_fidelity(stem, "emulated, 2 ticks late", emulate_multirate(text, fs::path(scene).parent_path(), e), md);
      } else {
        const FidelityResult r = measure_multirate(scene, o->duration, o->rate_hz, fs::path(o->out) / (stem + ".trec"));
        print_fidelity(stem, "threads", r, md);
      }
    }
  });
}

}  // namespace trocar::cli
