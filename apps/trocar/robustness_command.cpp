#include "robustness_command.h"

#include <algorithm>
#include <chrono>
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
#include "trocar/study/robustness.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct RobustnessArgs {
  std::vector<std::string> organs;   ///< folders of organ meshes (default: ../shared/data/meshes if there)
  std::string out = "study-robustness";
  std::vector<std::string> methods;  ///< default: every method
  std::vector<std::string> motions;  ///< default: every motion
  bool no_generated = false;
  bool quick = false;                ///< one small generated organ, press and poke-1, sdf (CI)
  std::uint64_t seed = 1;
};

/// The shared meshes beside the checkout or the working directory, if any.
std::vector<fs::path> default_organ_dirs() {
  std::vector<fs::path> out;
  for (const fs::path& p : {fs::path("../shared/data/meshes"), fs::path(TROCAR_SOURCE_SCENES) / "../../shared/data/meshes"}) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      out.push_back(fs::weakly_canonical(p, ec));
      break;
    }
  }
  return out;
}

std::string fixed(double x, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

void write_csv(const fs::path& path, const std::vector<SuiteRun>& runs) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  f << "organ,source,vertices,triangles,motion,method,steps,step_median_us,step_p99_us,deform_median_us,"
       "deform_p99_us,projection_median_us,deform_ns_per_vertex_contact,cg_mean,cg_mean_contact,cg_max,contact_steps,"
       "penetration_p99_mm,penetration_max_mm,tunneling_events,force_max_N,raw_force_max_N,stable\n";
  f << std::setprecision(6);
  for (const SuiteRun& r : runs)
    f << r.organ << ',' << r.source << ',' << r.vertices << ',' << r.triangles << ',' << r.motion << ',' << r.method
      << ',' << r.steps << ',' << r.step_median_us << ',' << r.step_p99_us << ',' << r.deform_median_us << ','
      << r.deform_p99_us << ',' << r.projection_median_us << ',' << r.deform_ns_per_vertex_contact << ',' << r.cg_mean << ',' << r.cg_mean_contact
      << ',' << r.cg_max << ',' << r.contact_steps << ',' << r.penetration_p99 * 1e3 << ','
      << r.penetration_max * 1e3 << ',' << r.tunneling << ',' << r.force_max << ',' << r.raw_force_max << ','
      << (r.stable ? "true" : "false") << '\n';
}

/// Whether a run meets the targets (docs/robustness.md): the step budget by size, and
/// the contact targets for motions up to 1 m/s.
struct Verdict {
  bool step = true, contact = true;
};
Verdict judge(const SuiteRun& r) {
  Verdict v;
  const bool small = r.triangles <= 12000;
  v.step = small ? (r.step_median_us <= 1000 && r.step_p99_us <= 1500) : r.step_median_us <= 2500;
  const bool in_scope = r.motion != "poke-2" && r.motion != "grasp-lift";
  v.contact = !in_scope || (r.penetration_p99 <= 0.5e-3 && r.penetration_max <= 1e-3 && r.tunneling == 0);
  v.contact = v.contact && r.stable;
  return v;
}

void write_markdown(const fs::path& path, const std::vector<SuiteRun>& runs, double wall_s, bool plots) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  f << "# Robustness suite\n\n"
    << runs.size() << " runs, " << fixed(wall_s, 1) << " s wall. Data: `robustness.csv`"
    << (plots ? "; plots: `step_vs_triangles.svg`, `penetration_p99.svg`." : " (gnuplot not found: no plots).")
    << "\n\nStep and deformation in µs (the step without its metrics stage: the real-time step has metrics "
       "off), the sdf projection's share of the deformation, the integrator alone per vertex in "
       "contact, CG iterations per step (mean over the steps with contact), penetration after the response "
       "in mm, tunneling events, largest force on the instrument (clamped at max_force as the device sees it). "
       "✓/✗: the step budget (≤ 1 ms median and ≤ 1.5 ms p99 up to 12K triangles, ≤ 2.5 ms median above) and "
       "the contact targets (p99 ≤ 0.5 mm, max ≤ 1 mm, no tunneling; judged up to 1 m/s, `poke-2` and "
       "`grasp-lift` reported only).\n\n";
  std::map<std::string, std::vector<const SuiteRun*>> by_method;
  for (const SuiteRun& r : runs) by_method[r.method].push_back(&r);
  for (const auto& [method, list] : by_method) {
    std::size_t step_ok = 0, contact_ok = 0;
    for (const SuiteRun* r : list) {
      const Verdict v = judge(*r);
      step_ok += v.step;
      contact_ok += v.contact;
    }
    f << "## " << method << ": step budget met in " << step_ok << "/" << list.size() << ", contact targets in "
      << contact_ok << "/" << list.size() << "\n\n"
      << "| organ | T | motion | step med | step p99 | deform med | projection med | integrator ns/V (contact) | CG (contact) | "
         "p99 pen | max pen | tunnel | max F (N) | step | contact |\n"
      << "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:-:|:-:|\n";
    for (const SuiteRun* r : list) {
      const Verdict v = judge(*r);
      f << "| " << r->organ << " | " << r->triangles << " | " << r->motion << " | " << fixed(r->step_median_us, 0)
        << " | " << fixed(r->step_p99_us, 0) << " | " << fixed(r->deform_median_us, 0) << " | "
        << fixed(r->projection_median_us, 0) << " | "
        << fixed(r->deform_ns_per_vertex_contact, 0) << " | " << fixed(r->cg_mean_contact, 1) << " | "
        << fixed(r->penetration_p99 * 1e3, 3) << " | " << fixed(r->penetration_max * 1e3, 3) << " | " << r->tunneling
        << " | " << fixed(r->force_max, 2) << (r->stable ? "" : " UNSTABLE") << " | " << (v.step ? "✓" : "✗")
        << " | " << (v.contact ? "✓" : "✗") << " |\n";
    }
    f << "\n";
  }
}

bool write_plots(const fs::path& dir, const std::vector<SuiteRun>& runs) {
  std::map<std::string, int> methods;
  for (const SuiteRun& r : runs) methods[r.method] = 0;
  std::ofstream gp(dir / "plots.gp");
  gp << "set datafile separator ','\nset terminal svg size 900,560 dynamic\nset key outside right\nset grid\n"
        "set output 'step_vs_triangles.svg'\nset logscale x\nset xlabel 'triangles'\n"
        "set ylabel 'step median without metrics (us)'\nset title 'Step time vs organ size (every motion)'\nplot ";
  bool first = true;
  for (const auto& [method, unused] : methods) {
    gp << (first ? "" : ", \\\n     ") << "'robustness.csv' using 4:((strcol(6) eq '" << method
       << "') ? $8 : NaN) with points pt 7 title '" << method << "'";
    first = false;
  }
  gp << ", 1000 with lines dt 2 title '1 ms'\n"
        "set output 'penetration_p99.svg'\nset ylabel 'p99 penetration (mm)'\nset logscale y\n"
        "set title 'p99 penetration vs organ size (every motion; runs at 0 not drawn on the log scale)'\nplot ";
  first = true;
  for (const auto& [method, unused] : methods) {
    gp << (first ? "" : ", \\\n     ") << "'robustness.csv' using 4:((strcol(6) eq '" << method
       << "' && $18 > 0) ? $18 : NaN) with points pt 7 title '" << method << "'";
    first = false;
  }
  gp << ", 0.5 with lines dt 2 title '0.5 mm'\n";
  gp.close();
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) return false;
  const std::string cmd = "cd '" + dir.string() + "' && gnuplot plots.gp";
  return std::system(cmd.c_str()) == 0;
}

void run_robustness(const RobustnessArgs& a) {
  std::vector<SuiteOrgan> organs;
  if (a.quick) {
    std::vector<SuiteOrgan> family = generated_organs(a.seed);
    organs.push_back(std::move(family.front()));
  } else {
    std::vector<fs::path> dirs(a.organs.begin(), a.organs.end());
    if (dirs.empty()) dirs = default_organ_dirs();
    for (const fs::path& d : dirs) {
      std::error_code ec;
      if (!fs::is_directory(d, ec)) throw Error("--organs: no such folder " + d.string());
      for (SuiteOrgan& o : organs_in(d, "shared")) organs.push_back(std::move(o));
    }
    if (!a.no_generated)
      for (SuiteOrgan& o : generated_organs(a.seed)) organs.push_back(std::move(o));
  }
  if (organs.empty()) throw Error("no organs (give --organs DIR or drop --no-generated)");

  std::vector<SuiteMotion> motions;
  const std::vector<SuiteMotion> every = all_suite_motions();
  const std::vector<std::string> motion_names =
      a.quick ? std::vector<std::string>{"press", "poke-1"} : a.motions;
  for (const std::string& name : motion_names) {
    const auto it = std::find_if(every.begin(), every.end(), [&](SuiteMotion m) { return name == suite_motion_name(m); });
    if (it == every.end()) throw Error("--motions: unknown motion \"" + name + "\"");
    motions.push_back(*it);
  }
  if (motions.empty()) motions = every;
  std::vector<ResponseMethod> methods;
  const std::vector<std::string> method_names = a.quick ? std::vector<std::string>{"sdf"} : a.methods;
  for (const std::string& name : method_names) {
    const auto m = parse_response_method(name);
    if (!m) throw Error("--methods: unknown method \"" + name + "\" (known: sdf, obb, primitive, normal, project)");
    methods.push_back(*m);
  }
  if (methods.empty())
    methods = {ResponseMethod::kSdf, ResponseMethod::kProject, ResponseMethod::kObb, ResponseMethod::kPrimitive,
               ResponseMethod::kNormal};

  const fs::path out = a.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error("cannot create " + out.string() + ": " + ec.message());
  const auto start = std::chrono::steady_clock::now();
  std::vector<SuiteRun> runs;
  const std::size_t total = organs.size() * motions.size() * methods.size();
  for (const SuiteOrgan& organ : organs)
    for (SuiteMotion motion : motions)
      for (ResponseMethod method : methods) {
        runs.push_back(run_suite_case(organ, motion, method));
        const SuiteRun& r = runs.back();
        std::cout << "[" << runs.size() << "/" << total << "] " << r.organ << " (" << r.triangles << " T) "
                  << r.motion << " " << r.method << ": step " << fixed(r.step_median_us, 0) << "/"
                  << fixed(r.step_p99_us, 0) << " us, CG " << fixed(r.cg_mean_contact, 1) << ", pen p99 "
                  << fixed(r.penetration_p99 * 1e3, 3) << " max " << fixed(r.penetration_max * 1e3, 3)
                  << " mm, tunnel " << r.tunneling << (r.stable ? "" : " UNSTABLE") << std::endl;
      }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_csv(out / "robustness.csv", runs);
  const bool plots = write_plots(out, runs);
  write_markdown(out / "robustness.md", runs, wall, plots);
  std::cout << "wrote " << (out / "robustness.csv").string() << " and " << (out / "robustness.md").string()
            << (plots ? " with SVG plots" : " (gnuplot not found: no plots; plots.gp written)") << "\n";
}

}  // namespace

void add_robustness_command(CLI::App& study) {
  auto a = std::make_shared<RobustnessArgs>();
  CLI::App* cmd = study.add_subcommand(
      "robustness", "Every organ x motion x response method: step time, CG iterations, penetration, tunneling");
  cmd->add_option("--organs", a->organs, "Folder(s) of organ meshes (default: ../shared/data/meshes when present)");
  cmd->add_option("--out", a->out, "Output folder (robustness.csv, robustness.md, SVG plots)")->capture_default_str();
  cmd->add_option("--methods", a->methods, "Response methods (default: sdf project obb primitive normal)");
  cmd->add_option("--motions", a->motions, "Motions (default: press slide poke-0.2 poke-1 poke-2 grasp-lift)");
  cmd->add_option("--seed", a->seed, "Seed of the generated organ family")->capture_default_str();
  cmd->add_flag("--no-generated", a->no_generated, "Leave out the generated organ family");
  cmd->add_flag("--quick", a->quick, "One small generated organ, press and poke-1, sdf (for CI)");
  cmd->callback([a] { run_robustness(*a); });
}

}  // namespace trocar::cli
