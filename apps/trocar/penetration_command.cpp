#include "penetration_command.h"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "trocar/study/penetration.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct PenetrationArgs {
  std::string out = "study-penetration";  ///< output folder
  std::string scenes;                     ///< folder of stab.json and probe_press_slide.json
  bool quick = false;                     ///< a tiny sweep (CI)
};

/// The shipped scenes folder: --scenes, else ./scenes, else the source tree's.
fs::path scenes_dir(const PenetrationArgs& a) {
  if (!a.scenes.empty()) return a.scenes;
  if (fs::is_regular_file("scenes/stab.json")) return "scenes";
  return TROCAR_SOURCE_SCENES;
}

void run(const PenetrationArgs& a) {
  const PenetrationSweep sweep = a.quick ? PenetrationSweep::quick() : PenetrationSweep::full();
  const auto start = std::chrono::steady_clock::now();
  const auto print = [](const PenetrationRow& r, std::size_t done, std::size_t total) {
    std::cout << "[" << done << "/" << total << "] " << r.scene << " " << r.method << " " << r.period_ms << " ms "
              << r.speed << " m/s: max " << millimetres(r.penetration_max) << " mm, p99 "
              << millimetres(r.penetration_p99) << " mm, tunneling " << r.tunneling << (r.stable ? "" : " UNSTABLE")
              << std::endl;
  };
  const std::vector<PenetrationRow> rows = run_penetration_sweep(sweep, scenes_dir(a), print);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const fs::path out = a.out;
  const bool plots = write_penetration_report(out, rows, sweep.variants, wall);
  std::cout << "wrote " << (out / "penetration.csv").string() << ", " << (out / "summary.md").string()
            << (plots ? " and SVG plots" : " (gnuplot not found: no plots; plots.gp written)") << "\n";
}

}  // namespace

void add_penetration_command(CLI::App& study) {
  auto a = std::make_shared<PenetrationArgs>();
  CLI::App* cmd = study.add_subcommand(
      "penetration", "Residual penetration and tunneling vs speed × response method × detection period");
  cmd->add_option("--out", a->out, "Output folder (CSV, summary.md, SVG plots)")->capture_default_str();
  cmd->add_option("--scenes", a->scenes, "Folder holding stab.json and probe_press_slide.json (default: ./scenes)");
  cmd->add_flag("--quick", a->quick, "A tiny sweep (one scene, one speed, two methods, two periods) for CI");
  cmd->callback([a] { run(*a); });
}

}  // namespace trocar::cli
