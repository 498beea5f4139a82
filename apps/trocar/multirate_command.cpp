#include "multirate_command.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "trocar/scene/scene.h"
#include "trocar/study/fidelity.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

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
