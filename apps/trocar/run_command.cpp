#include "run_command.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_support.h"
#include "frame_size.h"
#include "realtime_command.h"
#include "burn_report.h"
#include "task_report.h"
#include "trocar/core/cpu_features.h"
#include "trocar/core/error.h"
#include "trocar/core/statistics.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"
#ifdef TROCAR_HAVE_RENDER
#include "trocar/render/frame_recorder.h"
#endif

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct Options {
  std::string scene;
  double duration = -1;
  std::string method;
  std::string report;
  std::string record;
  std::string session;    // --session FILE: a binary session recording of the headless run
  bool quiet = false;
  std::string frames;     // --frames DIR
  std::string video;      // --video FILE.mp4
  double fps = 30;
  std::string size = "1280x720";
  std::string camera = "scope";
  bool no_metrics = false;  // --no-metrics: the step as the real-time loop runs it
};

/// median, p99 and max of samples (core/statistics.h; 0 for none).
nlohmann::json summary(const std::vector<double>& v) {
  const Summary s = summarize(v);
  return {{"median", s.median}, {"p99", s.p99}, {"max", s.max}};
}

class Progress {
 public:
  Progress(bool quiet, std::size_t total) : quiet_(quiet), total_(total), tty_(isatty(fileno(stderr)) != 0) {}
  void update(std::size_t done, double sim_time) {
    if (quiet_ || total_ == 0) return;
    const auto percent = static_cast<int>(100 * done / total_);
    if (percent == last_) return;
    last_ = percent;
    if (tty_) {
      const int width = 40;
      const int filled = percent * width / 100;
      std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.3f s", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                   std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), percent, sim_time);
      if (done == total_) std::fprintf(stderr, "\n");
    } else if (percent % 10 == 0) {
      std::fprintf(stderr, "run: %d%% (t = %.3f s)\n", percent, sim_time);
    }
  }

 private:
  bool quiet_;
  std::size_t total_;
  bool tty_;
  int last_ = -1;
};

/// The step just taken as a session recording's step record: the actions pressed before it, and
/// each instrument's pose and force after it (mode 0: the scene's keyframes moved it).
StepRecord session_record(const Simulation& sim, const StepMetrics& m, double dt, const std::vector<std::uint32_t>& pressed) {
  StepRecord r;
  r.step = m.step_index;
  r.time_ns = static_cast<std::int64_t>(std::llround(m.time * 1e9));
  r.dt = dt;
  const StageTimings& t = m.timings;
  r.timing_us = {float(t.broad_phase), float(t.narrow_phase), float(t.response), float(t.deformation),
                 float(t.projection), float(t.step), 0.0F};
  r.contacts = m.contacts;
  const World& world = sim.world();
  r.instruments = static_cast<std::uint32_t>(world.instruments.size());
  for (std::size_t i = 0; i < world.instruments.size(); ++i) {
    StepInstrument& s = r.instrument[i];
    const Instrument& in = world.instruments[i].instrument;
    s.mode = 0;
    s.actions = pressed[i];
    s.pose = to_words(in.pose());
    s.jaw = in.jaw();
    const Vec3 f = sim.instrument_metrics()[i].force;
    s.force = {f.x(), f.y(), f.z()};
  }
  return r;
}

void run(const Options& o) {
  Scene scene = load_scene(o.scene);
  apply_method_option(scene, o.method);
  if (o.duration >= 0) scene.duration = o.duration;
  if (o.no_metrics) scene.settings.measure_penetration = false;
  const double dt = scene.timestep;
  const std::size_t steps = step_count(scene.duration, dt);

  Simulation sim = make_simulation(scene);
  const World& world = sim.world();
  // The task, when the scene states one: evaluated after every step (docs/procedure.md).
  std::unique_ptr<Procedure> procedure;
  if (scene.task) procedure = std::make_unique<Procedure>(*scene.task, world, scene.zones, scene.landmarks);
#ifdef TROCAR_HAVE_RENDER
  std::unique_ptr<FrameRecorder> frames;
  if (!o.frames.empty() || !o.video.empty()) {
    FrameSettings fs_settings;
    fs_settings.dir = !o.frames.empty() ? fs::path(o.frames) : fs::path(o.video + ".frames");
    fs_settings.fps = o.fps;
    parse_frame_size(o.size, "--size", fs_settings.width, fs_settings.height);
    fs_settings.camera = select_camera(scene.cameras, world, o.camera);
    fs_settings.textures = scene.textures;
    fs_settings.tissue_appearance = scene.tissue_appearance;
    fs_settings.rigid_appearance = scene.rigid_appearance;
    frames = std::make_unique<FrameRecorder>(world, fs_settings);
    frames->on_step(sim);  // frame 0: the scene at rest
  }
#else
  if (!o.frames.empty() || !o.video.empty())
    throw Error("--frames/--video: this trocar was built without the renderer (install libepoxy-dev and libpng-dev, "
                "rebuild)");
#endif

  std::unique_ptr<std::ofstream> record;
  const fs::path record_tmp = o.record.empty() ? fs::path() : fs::path(o.record + ".tmp");
  if (!o.record.empty()) {
    record = std::make_unique<std::ofstream>(record_tmp);
    if (!*record) throw Error(o.record + ": cannot write");
    *record << "time_s";
    for (const InstrumentBody& b : world.instruments)
      for (const char* c : {"x", "y", "z", "qw", "qx", "qy", "qz", "jaw", "fx", "fy", "fz", "tx", "ty", "tz"})
        *record << "," << b.name << "_" << c;
    *record << ",contacts,penetration_m,tunneling,kinetic_J,elastic_J,motion_us,broad_phase_us,narrow_phase_us,"
               "response_us,deformation_us,metrics_us,step_us\n";
    record->precision(9);
  }

  // The session recording (docs/recording.md): what `trocar replay` redoes and `trocar score`
  // assesses. Each step's record carries the actions pressed before it; the instruments follow the
  // recorded scene's keyframes (mode 0), so the replay redoes exactly this run.
  std::unique_ptr<RecordingWriter> session;
  const fs::path session_tmp = o.session.empty() ? fs::path() : fs::path(o.session + ".tmp");
  if (!o.session.empty()) {
    if (world.instruments.size() > kMaxRuntimeInstruments)
      throw Error("--session: a session recording holds at most " + std::to_string(kMaxRuntimeInstruments) +
                  " instruments; the scene has " + std::to_string(world.instruments.size()));
    RecordingHeader h;
    h.instruments = static_cast<std::uint32_t>(world.instruments.size());
    h.haptic_rate_hz = 1 / dt;  // no haptic loop: physics steps in lock-step at the scene's timestep
    h.timestep = dt;
    h.mode = 1;
    h.kernel_path = kernel_path_name(kernel_path());
    h.scene_path = fs::absolute(o.scene).lexically_normal().string();
    h.scene_text = read_scene_text(o.scene);
    session = std::make_unique<RecordingWriter>(session_tmp, h, steps + 16);  // never full: nothing dropped
  }

  std::vector<double> t_broad, t_narrow, t_response, t_deform, t_step, t_burning;
  for (auto* v : {&t_broad, &t_narrow, &t_response, &t_deform, &t_step}) v->reserve(steps);
  std::vector<double> depths, forces;
  std::uint64_t pairs_total = 0, pairs_max = 0, steps_with_contact = 0, tunneling = 0;
  Progress progress(o.quiet, steps);
  // Scripted actions (scene "events": fire, exchange) due before the next step's end.
  // Collected per instrument and applied in index order, as a replay applies a step's actions.
  ActionScript actions(scene.actions);
  std::vector<std::uint32_t> pressed(world.instruments.size(), 0);
  const auto play_actions = [&] {
    std::fill(pressed.begin(), pressed.end(), 0U);
    actions.play_before(sim.time() + dt, [&](std::size_t i, std::uint32_t bit) {
      if (i < pressed.size()) pressed[i] |= bit;
    });
    for (std::size_t i = 0; i < pressed.size(); ++i)
      if (pressed[i] != 0) apply_actions(sim, i, pressed[i], procedure.get());
  };
  play_actions();
  const auto wall0 = std::chrono::steady_clock::now();
  std::size_t done = 0;
  const DriveResult drive_result = drive(sim, dt, steps, [&](const StepMetrics& m) {
    t_broad.push_back(m.timings.broad_phase);
    t_narrow.push_back(m.timings.narrow_phase);
    t_response.push_back(m.timings.response);
    t_deform.push_back(m.timings.deformation);
    t_step.push_back(m.timings.step);
    if (m.energy > 0) t_burning.push_back(m.timings.step);  // an electrode burning tissue this step
    pairs_total += m.contacts;
    pairs_max = std::max<std::uint64_t>(pairs_max, m.contacts);
    steps_with_contact += m.contacts > 0 ? 1 : 0;
    tunneling += m.tunneling_events;
    if (procedure) procedure->update(sim);
    if (m.vertices_inside > 0) depths.push_back(m.penetration_max);
    double force = 0;
    for (const InstrumentMetrics& im : sim.instrument_metrics()) force = std::max(force, im.force.norm());
    forces.push_back(force);
    if (record) {
      *record << m.time;
      for (std::size_t i = 0; i < world.instruments.size(); ++i) {
        const Instrument& in = world.instruments[i].instrument;
        const Pose& p = in.pose();
        const InstrumentMetrics& im = sim.instrument_metrics()[i];
        *record << "," << p.translation.x() << "," << p.translation.y() << "," << p.translation.z() << ","
                << p.rotation.w() << "," << p.rotation.x() << "," << p.rotation.y() << "," << p.rotation.z() << ","
                << in.jaw() << "," << im.force.x() << "," << im.force.y() << "," << im.force.z() << ","
                << im.torque.x() << "," << im.torque.y() << "," << im.torque.z();
      }
      const StageTimings& t = m.timings;
      *record << "," << m.contacts << "," << m.penetration_max << "," << m.tunneling_events << "," << m.kinetic_energy
              << "," << m.elastic_energy << "," << t.motion << "," << t.broad_phase << "," << t.narrow_phase << ","
              << t.response << "," << t.deformation << "," << t.metrics << "," << t.step << "\n";
    }
#ifdef TROCAR_HAVE_RENDER
    if (frames) {
      if (procedure) {
        const TaskView view = procedure->view();
        frames->on_step(sim, &view);
      } else {
        frames->on_step(sim);
      }
    }
#endif
    if (session) session->push_step(session_record(sim, m, dt, pressed));
    play_actions();
    progress.update(++done, m.time);
  });
  const bool stable = drive_result.stable;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  const nlohmann::json depth = summary(depths);
  const double depth_mean = mean(depths), force_mean = mean(forces);
  const double force_max = forces.empty() ? 0 : *std::max_element(forces.begin(), forces.end());

  nlohmann::json report = {
      {"scene", scene.name},
      {"method", response_method_name(sim.settings().response.method)},
      {"depth_cap", sim.settings().response.depth_cap},
      {"correction_speed", sim.settings().response.correction_speed},
      {"steps", done},
      {"timestep_s", dt},
      {"sim_time_s", sim.time()},
      {"wall_time_s", wall},
      {"timing_us",
       {{"broad_phase", summary(t_broad)},
        {"narrow_phase", summary(t_narrow)},
        {"response", summary(t_response)},
        {"deformation", summary(t_deform)},
        {"step", summary(t_step)}}},
      {"contacts",
       {{"pairs_total", pairs_total}, {"pairs_max_per_step", pairs_max}, {"steps_with_contact", steps_with_contact}}},
      {"penetration_m", {{"max", depth["max"]}, {"mean", depth_mean}, {"p99", depth["p99"]}}},
      {"tunneling_events", tunneling},
      {"instrument_force_N", {{"max", force_max}, {"mean", force_mean}}},
      {"stable", stable},
      {"state_hash", hash_hex(sim.state_hash())},
  };
  if (procedure) report["task"] = task_report(*procedure);
  std::string where_unstable;
  if (!stable) {
    // Where it blew up: the fastest vertex of the first unstable step (the run stops there).
    const Simulation::FastestVertex f = sim.fastest_vertex();
    if (f.tissue < sim.world().tissues.size()) {
      const std::string& tissue = sim.world().tissues[f.tissue]->name;
      report["unstable"] = {{"time_s", sim.time()}, {"tissue", tissue}, {"vertex", f.vertex}, {"speed_m_s", f.speed},
                            {"position_m", {f.position.x(), f.position.y(), f.position.z()}}};
      char line[256];
      std::snprintf(line, sizeof line, "unstable at t = %.3f s: %s vertex %u moving %.3g m/s at (%.1f, %.1f, %.1f) mm\n",
                    sim.time(), tissue.c_str(), f.vertex, f.speed, 1e3 * f.position.x(), 1e3 * f.position.y(),
                    1e3 * f.position.z());
      where_unstable = line;
    }
  }
  if (has_electrosurgery(sim)) {
    report["electrosurgery"] = electrosurgery_report(sim);  // burn_report.h
    report["timing_us"]["step_while_burning"] = summary(t_burning);
  }
  if (record) {
    record->close();
    fs::rename(record_tmp, o.record);
  }
  if (session) {
    finish_recording(*session, sim);
    fs::rename(session_tmp, o.session);
    report["session"] = o.session;
    if (!o.quiet) std::printf("session: %s (%zu steps)\n", o.session.c_str(), done);
  }
#ifdef TROCAR_HAVE_RENDER
  if (frames) {
    report["frames"] = {{"count", frames->frames()}, {"fps", o.fps}, {"size", o.size},
                        {"mean_frame_ms", frames->mean_frame_ms()}, {"renderer", frames->renderer_description()}};
    if (!o.quiet)
      std::printf("frames: %zu PNGs in %s (%.1f ms each, %s)\n", frames->frames(), frames->frame_path(0).parent_path().c_str(),
                  frames->mean_frame_ms(), frames->renderer_description().c_str());
    if (!o.video.empty()) {
      const std::string why = encode_video(frames->frame_path(0).parent_path(), o.fps, o.video);
      if (!why.empty()) throw Error("--video: " + why);
      if (!o.quiet) std::printf("video: %s\n", o.video.c_str());
    }
  }
#endif
  if (!o.report.empty()) write_atomically(o.report, report.dump(2) + "\n");
  if (!o.quiet)
    std::printf("%s: %zu steps, %.3f s simulated in %.3f s; step median %.1f us; %s; hash %s\n", scene.name.c_str(),
                done, sim.time(), wall, report["timing_us"]["step"]["median"].get<double>(),
                stable ? "stable" : "UNSTABLE", hash_hex(sim.state_hash()).c_str());
  if (!o.quiet) std::fputs(where_unstable.c_str(), stdout);
  if (procedure && !o.quiet) print_task(*procedure);
}

}  // namespace

void add_run_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("run", "Run a scene headless and write a report");
  cmd->add_option("scene", options->scene, "Scene file (JSON, docs/scene.md)")->required();
  cmd->add_option("--duration", options->duration, "Simulated seconds (default: the scene's duration)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--method", options->method, "Response method: obb, sdf, primitive, normal, project");
  cmd->add_option("--report", options->report, "Write the run report (JSON) to this file");
  cmd->add_option("--record", options->record, "Write a per-step CSV to this file");
  cmd->add_option("--session", options->session,
                  "Write a session recording (binary, docs/recording.md) that `trocar replay` redoes and `trocar "
                  "score` assesses");
  cmd->add_flag("--quiet,-q", options->quiet, "Print nothing but errors");
  cmd->add_flag("--no-metrics", options->no_metrics,
                "No exact penetration and tunneling metrics: the step as the real-time loop runs it (its timings "
                "are the budget's; penetration and tunneling report 0)");
  cmd->add_option("--frames", options->frames, "Render PNG frames headless (EGL) into this folder");
  cmd->add_option("--video", options->video, "Encode the frames into this MP4 with ffmpeg (frames in FILE.frames/ "
                                             "unless --frames names a folder)");
  cmd->add_option("--fps", options->fps, "Frames per simulated second (default 30)")->check(CLI::Range(0.001, 1000.0));
  cmd->add_option("--size", options->size, "Frame size WIDTHxHEIGHT (default 1280x720)");
  cmd->add_option("--camera", options->camera, "Camera: scope (the scene's first, default), orbit, or a scene camera's name");
  auto rt = std::make_shared<RealtimeOptions>();
  auto realtime = std::make_shared<bool>(false);
  cmd->add_flag("--realtime", *realtime,
                "Run at wall-clock speed on the real-time runtime (haptic + physics threads, devices); "
                "--duration is then wall-clock seconds and --record writes a binary session recording");
  cmd->add_option("--haptic-rate", rt->rate_hz, "Haptic rate in Hz (with --realtime; 1000, 4000, 10000)")
      ->check(CLI::Range(1.0, 100000.0));
  cmd->add_flag("--lockstep", rt->lockstep, "Physics inside the haptic tick (with --realtime)");
  cmd->add_flag("--metrics", rt->metrics, "Exact penetration metrics in real time (off by default there)");
  cmd->callback([options, rt, realtime, &exit_code]() {
    if (*realtime) {
      rt->scene = options->scene;
      rt->duration = options->duration;
      rt->method = options->method;
      rt->report = options->report;
      rt->record = options->record;
      rt->quiet = options->quiet;
      run_realtime(*rt);
      return;
    }
    if (rt->lockstep || rt->metrics) throw Error("--lockstep and --metrics go with --realtime");
    if (!options->session.empty() && !options->method.empty())
      throw Error("--session records the scene as written: set its response.method instead of --method");
    if (options->frames.empty() && options->video.empty() &&
        (options->camera != "scope" || options->size != "1280x720" || options->fps != 30))
      throw Error("--camera, --size and --fps go with --frames or --video");
    run(*options);
    (void)exit_code;
  });
}

}  // namespace trocar::cli
