#include "study_command.h"

#include "realtime_command.h"
#include "robustness_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct StudyArgs {
  std::string out = "study-penetration";  ///< output folder
  std::string scenes;                     ///< folder of stab.json and probe_press_slide.json
  bool quick = false;                     ///< a tiny sweep (CI)
};

/// One point of the sweep.
struct StudyRow {
  std::string scene;            ///< scene file stem
  std::string method;           ///< response method name
  Real period_ms = 1;           ///< detection period (ms)
  Real speed = 0;               ///< instrument speed on every moving segment (m/s)
  std::size_t steps = 0;        ///< steps simulated
  Real penetration_max = 0;     ///< m, max over steps
  Real penetration_p99 = 0;     ///< m, p99 over the steps with a vertex inside (0 if none)
  std::uint64_t tunneling = 0;  ///< Σ tunneling events
  std::uint64_t applied = 0;    ///< Σ applied contacts
  bool stable = true;           ///< finite throughout
};

/// The shipped scenes folder: --scenes, else ./scenes, else the source tree's.
fs::path scenes_dir(const StudyArgs& a) {
  if (!a.scenes.empty()) return a.scenes;
  if (fs::is_regular_file("scenes/stab.json")) return "scenes";
  return TROCAR_SOURCE_SCENES;
}

/// The keyframes with every moving segment re-timed to `speed` (m/s); holds keep their length.
std::vector<Keyframe> retime(std::span<const Keyframe> keys, Real speed) {
  std::vector<Keyframe> out(keys.begin(), keys.end());
  for (std::size_t i = 1; i < out.size(); ++i) {
    const Real length = (keys[i].position - keys[i - 1].position).norm();
    const Real dt = length > 0 ? length / speed : keys[i].t - keys[i - 1].t;
    out[i].t = out[i - 1].t + dt;
  }
  return out;
}

Real p99(std::vector<Real> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1;
  return v[std::min(k, v.size() - 1)];
}

/// A response variant of the sweep: a method, with or without the depth cap (obb, project) and
/// the gate on the position correction (project, primitive).
struct Variant {
  ResponseMethod method;
  bool depth_cap = true;
  bool gated = true;
  /// "obb", …; "obb-uncapped" for the seed's step 7 verbatim; "project-ungated" and
  /// "primitive-ungated" for the full correction at every contact.
  std::string name() const {
    std::string n = response_method_name(method);
    const bool capped_kind = method == ResponseMethod::kObb || method == ResponseMethod::kProject;
    const bool corrects = method == ResponseMethod::kProject || method == ResponseMethod::kPrimitive;
    if (capped_kind && !depth_cap) n += "-uncapped";
    if (corrects && !gated) n += "-ungated";
    return n;
  }
};

StudyRow run_point(const fs::path& file, const Variant& variant, Real period, Real speed) {
  Scene scene = load_scene(file);
  scene.settings.response.method = variant.method;
  scene.settings.response.depth_cap = variant.depth_cap;
  if (!variant.gated) scene.settings.response.correction_speed = 0;
  scene.settings.collision_period = period;
  Real end = 0;
  for (InstrumentBody& body : scene.world.instruments) {
    body.motion = KeyframeMotion(retime(body.motion.keyframes(), speed));
    end = std::max(end, body.motion.end_time());
  }
  const Real duration = end + 0.05;  // the motion, then 50 ms held
  Simulation sim(std::move(scene.world), scene.settings);
  StudyRow row;
  row.scene = file.stem().string();
  row.method = variant.name();
  row.period_ms = period * 1e3;
  row.speed = speed;
  row.steps = static_cast<std::size_t>(std::ceil(duration / scene.timestep));
  std::vector<Real> depths;
  for (std::size_t s = 0; s < row.steps; ++s) {
    const StepMetrics& m = sim.step(scene.timestep);
    row.stable = row.stable && m.finite;
    if (m.vertices_inside > 0) depths.push_back(m.penetration_max);
    row.penetration_max = std::max(row.penetration_max, m.penetration_max);
    row.tunneling += m.tunneling_events;
    row.applied += m.contacts_applied;
    if (!m.finite) break;
  }
  row.penetration_p99 = p99(std::move(depths));
  return row;
}

void write_csv(const fs::path& path, const std::vector<StudyRow>& rows) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  f << "scene,method,period_ms,speed_m_s,steps,penetration_max_mm,penetration_p99_mm,tunneling_events,"
       "contacts_applied,stable\n";
  f << std::setprecision(6);
  for (const StudyRow& r : rows)
    f << r.scene << ',' << r.method << ',' << r.period_ms << ',' << r.speed << ',' << r.steps << ','
      << r.penetration_max * 1e3 << ',' << r.penetration_p99 * 1e3 << ',' << r.tunneling << ',' << r.applied << ','
      << (r.stable ? "true" : "false") << '\n';
}

/// gnuplot script: per scene and metric, one SVG with a line per method × period.
bool write_plots(const fs::path& dir, const std::vector<StudyRow>& rows) {
  std::map<std::string, int> scenes, methods;
  std::map<Real, int> periods;
  for (const StudyRow& r : rows) {
    scenes[r.scene] = 0;
    methods[r.method] = 0;
    periods[r.period_ms] = 0;
  }
  const struct {
    const char* name;
    int column;
    const char* label;
  } metrics[] = {{"penetration_max", 6, "max penetration (mm)"},
                 {"penetration_p99", 7, "p99 penetration (mm)"},
                 {"tunneling", 8, "tunneling events"}};
  std::ofstream gp(dir / "plots.gp");
  gp << "set datafile separator ','\nset terminal svg size 900,560 dynamic\nset logscale x\n"
        "set xlabel 'instrument speed (m/s)'\nset key outside right\nset grid\n";
  for (const auto& [scene, unused_s] : scenes)
    for (const auto& m : metrics) {
      gp << "set output '" << scene << "_" << m.name << ".svg'\nset ylabel '" << m.label << "'\n"
         << "set title '" << scene << ": " << m.label << " vs speed'\nplot ";
      bool first = true;
      for (const auto& [method, unused_m] : methods)
        for (const auto& [period, unused_p] : periods) {
          gp << (first ? "" : ", \\\n     ") << "'penetration.csv' using 4:((strcol(1) eq '" << scene
             << "' && strcol(2) eq '" << method << "' && $3 == " << period << ") ? $" << m.column
             << " : NaN) with linespoints title '" << method << " " << period << " ms'";
          first = false;
        }
      gp << "\n";
    }
  gp.close();
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) return false;
  const std::string cmd = "cd '" + dir.string() + "' && gnuplot plots.gp";
  return std::system(cmd.c_str()) == 0;
}

std::string mm(Real m) {
  std::ostringstream s;
  s << std::setprecision(3) << m * 1e3;
  return s.str();
}

/// Worst values over speeds ≤ limit for one scene, method and period.
struct Worst {
  Real p99 = 0, max = 0;
  std::uint64_t tunneling = 0;
  bool any = false, stable = true;
};

Worst worst(const std::vector<StudyRow>& rows, const std::string& scene, const std::string& method, Real period_ms,
            Real limit) {
  Worst w;
  for (const StudyRow& r : rows)
    if (r.scene == scene && r.method == method && r.period_ms == period_ms && r.speed <= limit + 1e-12) {
      w.any = true;
      w.p99 = std::max(w.p99, r.penetration_p99);
      w.max = std::max(w.max, r.penetration_max);
      w.tunneling += r.tunneling;
      w.stable = w.stable && r.stable;
    }
  return w;
}

/// `variants`: the sweep's variants in order (their names head the table rows; those of obb and
/// project are judged against the goal).
void write_summary(const fs::path& path, const std::vector<StudyRow>& rows, const std::vector<Variant>& variants,
                   bool plots, double wall_s) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  std::map<std::string, int> scenes;
  for (const StudyRow& r : rows) scenes[r.scene] = 0;
  f << "# Penetration study\n\n"
    << rows.size() << " runs (" << std::setprecision(3) << wall_s << " s wall). Data: `penetration.csv`; "
    << (plots ? "plots: `*_penetration_max.svg`, `*_penetration_p99.svg`, `*_tunneling.svg`."
              : "no plots (gnuplot not found; `plots.gp` is the script to run).")
    << "\n\nPenetration is the depth of instrument vertices inside the closed organ after the response "
       "(signed distance, pseudonormals); p99 is over the steps with a vertex inside. Tunneling events as "
       "in DESIGN.md §6. Speed is the instrument's speed on every moving keyframe segment.\n\n"
       "In `stab` the probe is driven through the organ on purpose: its penetration and tunneling measure "
       "the piercing, not a failure of the response. The goal is judged on `probe_press_slide`.\n\n";
  for (const auto& [scene, unused] : scenes) {
    f << "## " << scene << ", speeds ≤ 1 m/s, worst over the sweep\n\n"
      << "| method | period (ms) | tunneling events | p99 penetration (mm) | max penetration (mm) | stable |\n"
      << "|---|---|---|---|---|---|\n";
    for (const Variant& variant : variants)
      for (Real period : {1.0, 2.0, 5.0}) {
        const std::string method = variant.name();
        const Worst w = worst(rows, scene, method, period, 1.0);
        if (!w.any) continue;
        f << "| " << method << " | " << period << " | " << w.tunneling << " | " << mm(w.p99) << " | " << mm(w.max)
          << " | " << (w.stable ? "yes" : "no") << " |\n";
      }
    f << "\n";
  }
  const std::string goal_scene = "probe_press_slide";
  f << "## Goal (" << goal_scene << ", 1 ms detection, up to 1 m/s): zero tunneling and p99 ≤ 0.5 mm\n\n";
  const Worst prim = worst(rows, goal_scene, "primitive", 1.0, 1.0);
  for (const Variant& variant : variants) {
    if (variant.method != ResponseMethod::kObb && variant.method != ResponseMethod::kProject) continue;
    const std::string method = variant.name();
    const Worst w = worst(rows, goal_scene, method, 1.0, 1.0);
    if (!w.any) continue;
    const bool met = w.tunneling == 0 && w.p99 <= 0.5e-3;
    f << "- `" << method << "`: " << (met ? "**met**" : "**not met**") << " — " << w.tunneling
      << " tunneling events, worst p99 " << mm(w.p99) << " mm, worst max " << mm(w.max) << " mm";
    if (prim.any)
      f << "; `primitive`: " << prim.tunneling << " events, p99 " << mm(prim.p99) << " mm (p99 ratio primitive/"
        << method << " = " << (w.p99 > 0 ? mm(prim.p99 / w.p99 * 1e-3) : std::string("inf")) << ")";
    f << ".\n";
  }
}

void run_study(const StudyArgs& a) {
  const fs::path dir = scenes_dir(a);
  const fs::path out = a.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error("cannot create " + out.string() + ": " + ec.message());
  std::vector<std::string> scenes = {"probe_press_slide", "stab"};
  std::vector<Real> speeds = {0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0};
  // obb and project with the depth cap (the simulator's), obb without it (the seed verbatim);
  // project and primitive with the gated correction (the simulator's) and without the gate.
  std::vector<Variant> methods = {{ResponseMethod::kObb},
                                  {ResponseMethod::kObb, false},
                                  {ResponseMethod::kPrimitive},
                                  {ResponseMethod::kPrimitive, true, false},
                                  {ResponseMethod::kNormal},
                                  {ResponseMethod::kProject},
                                  {ResponseMethod::kProject, true, false}};
  std::vector<Real> periods = {0.001, 0.002, 0.005};
  if (a.quick) {
    scenes = {"probe_press_slide"};
    speeds = {0.5};
    methods = {{ResponseMethod::kObb}, {ResponseMethod::kPrimitive}};
    periods = {0.001, 0.005};
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<StudyRow> rows;
  const std::size_t total = scenes.size() * speeds.size() * methods.size() * periods.size();
  for (const std::string& scene : scenes) {
    const fs::path file = dir / (scene + ".json");
    if (!fs::is_regular_file(file)) throw Error("scene not found: " + file.string());
    for (const Variant& method : methods)
      for (Real period : periods)
        for (Real speed : speeds) {
          rows.push_back(run_point(file, method, period, speed));
          const StudyRow& r = rows.back();
          std::cout << "[" << rows.size() << "/" << total << "] " << r.scene << " " << r.method << " "
                    << r.period_ms << " ms " << r.speed << " m/s: max " << mm(r.penetration_max) << " mm, p99 "
                    << mm(r.penetration_p99) << " mm, tunneling " << r.tunneling << (r.stable ? "" : " UNSTABLE")
                    << std::endl;
        }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_csv(out / "penetration.csv", rows);
  const bool plots = write_plots(out, rows);
  write_summary(out / "summary.md", rows, methods, plots, wall);
  std::cout << "wrote " << (out / "penetration.csv").string() << ", " << (out / "summary.md").string()
            << (plots ? " and SVG plots" : " (gnuplot not found: no plots; plots.gp written)") << "\n";
}

}  // namespace

void add_study_command(CLI::App& app, int& exit_code) {
  (void)exit_code;
  CLI::App* study = app.add_subcommand("study", "Measure the simulator's claims");
  study->require_subcommand(1);
  auto a = std::make_shared<StudyArgs>();
  CLI::App* pen = study->add_subcommand(
      "penetration", "Residual penetration and tunneling vs speed × response method × detection period");
  pen->add_option("--out", a->out, "Output folder (CSV, summary.md, SVG plots)")->capture_default_str();
  pen->add_option("--scenes", a->scenes, "Folder holding stab.json and probe_press_slide.json (default: ./scenes)");
  pen->add_flag("--quick", a->quick, "A tiny sweep (one scene, one speed, two methods, two periods) for CI");
  pen->callback([a] { run_study(*a); });
  add_robustness_command(*study);
  add_multirate_command(*study);
}

}  // namespace trocar::cli
