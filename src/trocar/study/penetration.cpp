#include "trocar/study/penetration.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <span>
#include <sstream>

#include "trocar/core/error.h"
#include "trocar/core/statistics.h"
#include "trocar/scene/scene.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;

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

void write_csv(const fs::path& path, const std::vector<PenetrationRow>& rows) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  f << "scene,method,period_ms,speed_m_s,steps,penetration_max_mm,penetration_p99_mm,tunneling_events,"
       "contacts_applied,stable\n";
  f << std::setprecision(6);
  for (const PenetrationRow& r : rows)
    f << r.scene << ',' << r.method << ',' << r.period_ms << ',' << r.speed << ',' << r.steps << ','
      << r.penetration_max * 1e3 << ',' << r.penetration_p99 * 1e3 << ',' << r.tunneling << ',' << r.applied << ','
      << (r.stable ? "true" : "false") << '\n';
}

/// gnuplot script: per scene and metric, one SVG with a line per method × period.
bool write_plots(const fs::path& dir, const std::vector<PenetrationRow>& rows) {
  std::map<std::string, int> scenes, methods;
  std::map<Real, int> periods;
  for (const PenetrationRow& r : rows) {
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

/// Worst values over speeds ≤ limit for one scene, method and period.
struct Worst {
  Real p99 = 0, max = 0;
  std::uint64_t tunneling = 0;
  bool any = false, stable = true;
};

Worst worst(const std::vector<PenetrationRow>& rows, const std::string& scene, const std::string& method,
            Real period_ms, Real limit) {
  Worst w;
  for (const PenetrationRow& r : rows)
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
void write_summary(const fs::path& path, const std::vector<PenetrationRow>& rows,
                   const std::vector<PenetrationVariant>& variants, bool plots, double wall_s) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  std::map<std::string, int> scenes;
  for (const PenetrationRow& r : rows) scenes[r.scene] = 0;
  f << "# Penetration study\n\n"
    << rows.size() << " runs (" << std::setprecision(3) << wall_s << " s wall). Data: `penetration.csv`; "
    << (plots ? "plots: `*_penetration_max.svg`, `*_penetration_p99.svg`, `*_tunneling.svg`."
              : "no plots (gnuplot not found; `plots.gp` is the script to run).")
    << "\n\nPenetration is the depth of instrument vertices inside the closed organ after the response "
       "(signed distance, pseudonormals); p99 is over the steps with a vertex inside. Tunneling events as "
       "in docs/penetration-study.md. Speed is the instrument's speed on every moving keyframe segment.\n\n"
       "In `stab` the probe is driven through the organ on purpose: its penetration and tunneling measure "
       "the piercing, not a failure of the response. The goal is judged on `probe_press_slide`.\n\n";
  for (const auto& [scene, unused] : scenes) {
    f << "## " << scene << ", speeds ≤ 1 m/s, worst over the sweep\n\n"
      << "| method | period (ms) | tunneling events | p99 penetration (mm) | max penetration (mm) | stable |\n"
      << "|---|---|---|---|---|---|\n";
    for (const PenetrationVariant& variant : variants)
      for (Real period : {1.0, 2.0, 5.0}) {
        const std::string method = variant.name();
        const Worst w = worst(rows, scene, method, period, 1.0);
        if (!w.any) continue;
        f << "| " << method << " | " << period << " | " << w.tunneling << " | " << millimetres(w.p99) << " | "
          << millimetres(w.max) << " | " << (w.stable ? "yes" : "no") << " |\n";
      }
    f << "\n";
  }
  const std::string goal_scene = "probe_press_slide";
  f << "## Goal (" << goal_scene << ", 1 ms detection, up to 1 m/s): zero tunneling and p99 ≤ 0.5 mm\n\n";
  const Worst prim = worst(rows, goal_scene, "primitive", 1.0, 1.0);
  for (const PenetrationVariant& variant : variants) {
    if (variant.method != ResponseMethod::kObb && variant.method != ResponseMethod::kProject) continue;
    const std::string method = variant.name();
    const Worst w = worst(rows, goal_scene, method, 1.0, 1.0);
    if (!w.any) continue;
    const bool met = w.tunneling == 0 && w.p99 <= 0.5e-3;
    f << "- `" << method << "`: " << (met ? "**met**" : "**not met**") << " — " << w.tunneling
      << " tunneling events, worst p99 " << millimetres(w.p99) << " mm, worst max " << millimetres(w.max) << " mm";
    if (prim.any)
      f << "; `primitive`: " << prim.tunneling << " events, p99 " << millimetres(prim.p99)
        << " mm (p99 ratio primitive/" << method << " = "
        << (w.p99 > 0 ? millimetres(prim.p99 / w.p99 * 1e-3) : std::string("inf")) << ")";
    f << ".\n";
  }
}

}  // namespace

std::string PenetrationVariant::name() const {
  std::string n = response_method_name(method);
  const bool capped_kind = method == ResponseMethod::kObb || method == ResponseMethod::kProject;
  const bool corrects = method == ResponseMethod::kProject || method == ResponseMethod::kPrimitive;
  if (capped_kind && !depth_cap) n += "-uncapped";
  if (corrects && !gated) n += "-ungated";
  return n;
}

PenetrationSweep PenetrationSweep::full() {
  PenetrationSweep s;
  s.scenes = {"probe_press_slide", "stab"};
  // obb and project with the depth cap (the simulator's), obb without it (the seed verbatim);
  // project and primitive with the gated correction (the simulator's) and without the gate.
  s.variants = {{ResponseMethod::kObb},     {ResponseMethod::kObb, false},     {ResponseMethod::kPrimitive},
                {ResponseMethod::kPrimitive, true, false}, {ResponseMethod::kNormal},
                {ResponseMethod::kProject}, {ResponseMethod::kProject, true, false}};
  s.periods = {0.001, 0.002, 0.005};
  s.speeds = {0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0};
  return s;
}

PenetrationSweep PenetrationSweep::quick() {
  PenetrationSweep s;
  s.scenes = {"probe_press_slide"};
  s.variants = {{ResponseMethod::kObb}, {ResponseMethod::kPrimitive}};
  s.periods = {0.001, 0.005};
  s.speeds = {0.5};
  return s;
}

PenetrationRow run_penetration_point(const fs::path& file, const PenetrationVariant& variant, Real period,
                                     Real speed) {
  Scene scene = load_scene(file);
  scene.settings.response.method = variant.method;
  scene.settings.response.depth_cap = variant.depth_cap;
  if (!variant.gated) scene.settings.response.correction_speed = 0;
  scene.settings.collision_period = period;
  Real end = 0;
  for (InstrumentBody& body : scene.world.instruments) {
    body.motion = KeyframeMotion(retime(body.motion.keyframes(), speed), body.motion.interpolation());
    end = std::max(end, body.motion.end_time());
  }
  const Real duration = end + 0.05;  // the motion, then 50 ms held
  Simulation sim = make_simulation(scene);
  PenetrationRow row;
  row.scene = file.stem().string();
  row.method = variant.name();
  row.period_ms = period * 1e3;
  row.speed = speed;
  row.steps = step_count(duration, scene.timestep);
  std::vector<double> depths;
  const DriveResult run = drive(sim, scene.timestep, row.steps, [&](const StepMetrics& m) {
    if (m.vertices_inside > 0) depths.push_back(m.penetration_max);
    row.penetration_max = std::max(row.penetration_max, m.penetration_max);
    row.tunneling += m.tunneling_events;
    row.applied += m.contacts_applied;
  });
  row.stable = run.stable;
  row.penetration_p99 = quantile(depths, 0.99);
  return row;
}

std::vector<PenetrationRow> run_penetration_sweep(
    const PenetrationSweep& sweep, const fs::path& scenes_dir,
    const std::function<void(const PenetrationRow&, std::size_t, std::size_t)>& progress) {
  std::vector<PenetrationRow> rows;
  for (const std::string& scene : sweep.scenes) {
    const fs::path file = scenes_dir / (scene + ".json");
    if (!fs::is_regular_file(file)) throw Error("scene not found: " + file.string());
    for (const PenetrationVariant& variant : sweep.variants)
      for (const Real period : sweep.periods)
        for (const Real speed : sweep.speeds) {
          rows.push_back(run_penetration_point(file, variant, period, speed));
          if (progress) progress(rows.back(), rows.size(), sweep.size());
        }
  }
  return rows;
}

bool write_penetration_report(const fs::path& out, const std::vector<PenetrationRow>& rows,
                              const std::vector<PenetrationVariant>& variants, double wall_s) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error("cannot create " + out.string() + ": " + ec.message());
  write_csv(out / "penetration.csv", rows);
  const bool plots = write_plots(out, rows);
  write_summary(out / "summary.md", rows, variants, plots, wall_s);
  return plots;
}

std::string millimetres(Real metres) {
  std::ostringstream s;
  s << std::setprecision(3) << metres * 1e3;
  return s.str();
}

}  // namespace trocar
