#include "robustness_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/study/robustness.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct RobustnessArgs {
  std::vector<std::string> organs;       ///< folders of organ meshes (default: ../shared/data/meshes if there)
  std::string out = "study-robustness";
  std::vector<std::string> solvers;      ///< --solvers (alias --methods); default xpbd sdf
  std::vector<std::string> materials;    ///< default light-soft medium heavy-stiff
  std::vector<std::string> instruments;  ///< default every instrument (hook-mesh when its file is there)
  std::vector<std::string> motions;      ///< default every motion
  bool no_generated = false;
  /// One small generated organ; light-soft and heavy-stiff, hook, press and poke-1, xpbd and sdf
  /// (CI). Lists given alongside replace these defaults.
  bool quick = false;
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
  if (!std::isfinite(x)) return x > 0 ? "inf" : (x < 0 ? "-inf" : "nan");
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

/// "1.2e-03" style, for the constraint errors (relative, from 1e-9 to 1).
std::string sci(double x) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(1) << x;
  return s.str();
}

/// The rest check's drift as a signed percentage ("+0.3 %"), "–" for other motions.
std::string drift_text(const SuiteRun& r) {
  if (!r.rest) return "–";
  if (!std::isfinite(r.energy_drift)) return "+inf";
  return (r.energy_drift >= 0 ? "+" : "") + fixed(100 * r.energy_drift, 1) + " %" + (r.energy_grew ? " grew" : "");
}

void write_csv(const fs::path& path, const std::vector<SuiteRun>& runs) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  // Columns (1-based, plots.gp reads 4, 5, 8, 11 and 24): the energy columns are empty except on
  // the rest check's rows.
  f << "organ,source,vertices,triangles,material,instrument,motion,solver,integrator,steps,step_median_us,"
       "step_p99_us,deform_median_us,deform_p99_us,projection_median_us,deform_ns_per_vertex_contact,cg_mean,"
       "cg_mean_contact,cg_max,substeps_max,constraint_error_max,constraint_error_median,contact_steps,"
       "penetration_p99_mm,penetration_max_mm,tunneling_events,force_max_N,raw_force_max_N,energy_first_J,"
       "energy_last_J,energy_drift,energy_grew,stable\n";
  f << std::setprecision(6);
  for (const SuiteRun& r : runs) {
    f << r.organ << ',' << r.source << ',' << r.vertices << ',' << r.triangles << ',' << r.material << ','
      << r.instrument << ',' << r.motion << ',' << r.solver << ',' << r.integrator << ',' << r.steps << ','
      << r.step_median_us << ',' << r.step_p99_us << ',' << r.deform_median_us << ',' << r.deform_p99_us << ','
      << r.projection_median_us << ',' << r.deform_ns_per_vertex_contact << ',' << r.cg_mean << ','
      << r.cg_mean_contact << ',' << r.cg_max << ',' << r.substeps_max << ',' << r.constraint_error_max << ','
      << r.constraint_error_median << ',' << r.contact_steps << ',' << r.penetration_p99 * 1e3 << ','
      << r.penetration_max * 1e3 << ',' << r.tunneling << ',' << r.force_max << ',' << r.raw_force_max << ',';
    if (r.rest)
      f << r.energy_first << ',' << r.energy_last << ',' << r.energy_drift << ',' << (r.energy_grew ? 1 : 0) << ',';
    else
      f << ",,,,";
    f << (r.stable ? "true" : "false") << '\n';
  }
}

/// Whether a run meets the suite's targets (docs/robustness.md): the step budget by size, and
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

/// "organ / material / instrument / motion".
std::string cell(const SuiteRun& r) { return r.organ + " / " + r.material + " / " + r.instrument + " / " + r.motion; }

/// The solvers in the order they first appear in `runs`.
std::vector<std::string> solver_order(const std::vector<SuiteRun>& runs) {
  std::vector<std::string> out;
  for (const SuiteRun& r : runs)
    if (std::find(out.begin(), out.end(), r.solver) == out.end()) out.push_back(r.solver);
  return out;
}

void write_summary(std::ofstream& f, const std::vector<SuiteRun>& runs) {
  f << "## Summary\n\n"
    << "Per solver: the runs meeting the step budget and the contact targets (the ✓ columns below), the "
       "worst cell by max penetration and by step p99, and the rest check (light-stiff, no contact, 0.5 s): "
       "the largest drift of the total energy (kinetic + elastic, mean over the last 0.1 s against the "
       "first 0.1 s) and the runs where it grew by more than "
    << fixed(100 * kSuiteEnergyGrowth, 0) << " %.\n\n"
    << "| solver | integrator | runs | step budget met | contact targets met | worst max pen (mm) | in | "
       "worst step p99 (µs) | in | unstable | rest: max drift | rest: energy grew |\n"
    << "|---|---|---:|---:|---:|---:|---|---:|---|---:|---:|---:|\n";
  for (const std::string& solver : solver_order(runs)) {
    std::size_t n = 0, step_ok = 0, contact_ok = 0, unstable = 0, rest = 0, grew = 0;
    const SuiteRun *worst_pen = nullptr, *worst_step = nullptr, *worst_drift = nullptr;
    std::string integrator;
    for (const SuiteRun& r : runs) {
      if (r.solver != solver) continue;
      integrator = r.integrator;
      ++n;
      const Verdict v = judge(r);
      step_ok += v.step;
      contact_ok += v.contact;
      unstable += !r.stable;
      if (!worst_pen || r.penetration_max > worst_pen->penetration_max) worst_pen = &r;
      if (!worst_step || r.step_p99_us > worst_step->step_p99_us) worst_step = &r;
      if (r.rest) {
        ++rest;
        grew += r.energy_grew;
        if (!worst_drift || r.energy_drift > worst_drift->energy_drift) worst_drift = &r;
      }
    }
    f << "| " << solver << " | " << integrator << " | " << n << " | " << step_ok << "/" << n << " | " << contact_ok
      << "/" << n << " | " << fixed(worst_pen->penetration_max * 1e3, 2) << " | " << cell(*worst_pen) << " | "
      << fixed(worst_step->step_p99_us, 0) << " | " << cell(*worst_step) << " | " << unstable << " | "
      << (worst_drift ? drift_text(*worst_drift) : "–") << " | " << (rest ? std::to_string(grew) + "/" + std::to_string(rest) : "–")
      << " |\n";
  }
  f << "\n";
}

void write_markdown(const fs::path& path, const std::vector<SuiteRun>& runs, double wall_s, bool plots) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write " + path.string());
  f << "# Robustness suite\n\n"
    << runs.size() << " runs, " << fixed(wall_s, 1) << " s wall. Data: `robustness.csv`"
    << (plots ? "; plots: `step_vs_triangles.svg`, `penetration_p99.svg`." : " (gnuplot not found: no plots).")
    << "\n\nStep and deformation in µs (the step without its metrics stage: the real-time step has metrics "
       "off), the sdf projection's share of the deformation, the integrator alone per vertex in "
       "contact, CG iterations per step (mean over the steps with contact; implicit solvers), xpbd substeps "
       "(max), the constraint error the solver left (max/median over the steps: the CG's relative residual "
       "for implicit Euler, the largest spring strain for xpbd), penetration after the response "
       "in mm, tunneling events, largest force on the instrument (clamped at max_force as the device sees it), "
       "the rest check's energy drift. "
       "✓/✗: the step budget (≤ 1 ms median and ≤ 1.5 ms p99 up to 12K triangles, ≤ 2.5 ms median above) and "
       "the contact targets (p99 ≤ 0.5 mm, max ≤ 1 mm, no tunneling; judged up to 1 m/s, `poke-2` and "
       "`grasp-lift` reported only).\n\n";
  write_summary(f, runs);
  for (const std::string& solver : solver_order(runs)) {
    std::vector<const SuiteRun*> list;
    for (const SuiteRun& r : runs)
      if (r.solver == solver) list.push_back(&r);
    std::size_t step_ok = 0, contact_ok = 0;
    for (const SuiteRun* r : list) {
      const Verdict v = judge(*r);
      step_ok += v.step;
      contact_ok += v.contact;
    }
    f << "## " << solver << ": step budget met in " << step_ok << "/" << list.size() << ", contact targets in "
      << contact_ok << "/" << list.size() << "\n\n"
      << "| organ | T | material | instrument | motion | step med | step p99 | deform med | projection med | "
         "integrator ns/V (contact) | CG (contact) | substeps | constraint err max/med | p99 pen | max pen | "
         "tunnel | max F (N) | energy drift | step | contact |\n"
      << "|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:-:|:-:|\n";
    for (const SuiteRun* r : list) {
      const Verdict v = judge(*r);
      f << "| " << r->organ << " | " << r->triangles << " | " << r->material << " | " << r->instrument << " | "
        << r->motion << " | " << fixed(r->step_median_us, 0) << " | " << fixed(r->step_p99_us, 0) << " | "
        << fixed(r->deform_median_us, 0) << " | " << fixed(r->projection_median_us, 0) << " | "
        << fixed(r->deform_ns_per_vertex_contact, 0) << " | " << fixed(r->cg_mean_contact, 1) << " | "
        << r->substeps_max << " | " << sci(r->constraint_error_max) << "/" << sci(r->constraint_error_median)
        << " | " << fixed(r->penetration_p99 * 1e3, 3) << " | " << fixed(r->penetration_max * 1e3, 3) << " | "
        << r->tunneling << " | " << fixed(r->force_max, 2) << (r->stable ? "" : " UNSTABLE") << " | "
        << drift_text(*r) << " | " << (v.step ? "✓" : "✗") << " | " << (v.contact ? "✓" : "✗") << " |\n";
    }
    f << "\n";
  }
}

bool write_plots(const fs::path& dir, const std::vector<SuiteRun>& runs) {
  // One series per (solver, material), in the order they first appear.
  std::vector<std::pair<std::string, std::string>> series;
  for (const SuiteRun& r : runs)
    if (std::find(series.begin(), series.end(), std::pair(r.solver, r.material)) == series.end())
      series.emplace_back(r.solver, r.material);
  std::ofstream gp(dir / "plots.gp");
  gp << "set datafile separator ','\nset terminal svg size 900,560 dynamic\nset key outside right\nset grid\n"
        "set output 'step_vs_triangles.svg'\nset logscale x\nset xlabel 'triangles'\n"
        "set ylabel 'step median without metrics (us)'\nset title 'Step time vs organ size (every motion)'\nplot ";
  bool first = true;
  for (const auto& [solver, material] : series) {
    gp << (first ? "" : ", \\\n     ") << "'robustness.csv' using 4:((strcol(8) eq '" << solver
       << "' && strcol(5) eq '" << material << "') ? $11 : NaN) with points pt 7 title '" << solver << " "
       << material << "'";
    first = false;
  }
  gp << ", 1000 with lines dt 2 title '1 ms'\n"
        "set output 'penetration_p99.svg'\nset ylabel 'p99 penetration (mm)'\nset logscale y\n"
        "set title 'p99 penetration vs organ size (every motion; runs at 0 not drawn on the log scale)'\nplot ";
  first = true;
  for (const auto& [solver, material] : series) {
    gp << (first ? "" : ", \\\n     ") << "'robustness.csv' using 4:((strcol(8) eq '" << solver
       << "' && strcol(5) eq '" << material << "' && $24 > 0) ? $24 : NaN) with points pt 7 title '" << solver
       << " " << material << "'";
    first = false;
  }
  gp << ", 0.5 with lines dt 2 title '0.5 mm'\n";
  gp.close();
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) return false;
  const std::string cmd = "cd '" + dir.string() + "' && gnuplot plots.gp";
  return std::system(cmd.c_str()) == 0;
}

/// `names` joined with ", ".
std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// One run to do: indices into the organs, instruments and solvers, a motion and a material name.
struct SuiteCase {
  std::size_t organ = 0;
  std::string material;
  std::size_t instrument = 0;
  SuiteMotion motion = SuiteMotion::kPress;
  std::size_t solver = 0;
};

void run_robustness(const RobustnessArgs& a) {
  // The lists: given, else --quick's, else the full suite's.
  const auto pick = [&](const std::vector<std::string>& given, std::vector<std::string> quick,
                        std::vector<std::string> full) {
    if (!given.empty()) return given;
    return a.quick ? quick : full;
  };
  const std::vector<std::string> solver_names = pick(a.solvers, {"xpbd", "sdf"}, {"xpbd", "sdf"});
  const std::vector<std::string> material_names =
      pick(a.materials, {"light-soft", "heavy-stiff"}, suite_contact_material_names());
  const std::vector<std::string> instrument_names = pick(a.instruments, {"hook"}, suite_instrument_names());
  std::vector<std::string> every_motion;
  for (const SuiteMotion m : all_suite_motions()) every_motion.emplace_back(suite_motion_name(m));
  const std::vector<std::string> motion_names = pick(a.motions, {"press", "poke-1"}, every_motion);

  std::vector<SuiteSolver> solvers;
  for (const std::string& name : solver_names) {
    const std::optional<SuiteSolver> s = parse_suite_solver(name);
    if (!s) throw Error("--solvers: unknown solver \"" + name + "\" (known: " + joined(suite_solver_names()) + ")");
    solvers.push_back(*s);
  }
  const std::vector<std::string> known_materials = suite_material_names();
  for (const std::string& name : material_names)
    if (std::find(known_materials.begin(), known_materials.end(), name) == known_materials.end())
      throw Error("--materials: unknown material \"" + name + "\" (known: " + joined(known_materials) + ")");
  std::vector<SuiteMotion> motions;
  for (const std::string& name : motion_names) {
    const std::optional<SuiteMotion> m = parse_suite_motion(name);
    if (!m) throw Error("--motions: unknown motion \"" + name + "\" (known: " + joined(every_motion) + ")");
    motions.push_back(*m);
  }

  std::vector<fs::path> dirs(a.organs.begin(), a.organs.end());
  for (const fs::path& d : dirs) {
    std::error_code ec;
    if (!fs::is_directory(d, ec)) throw Error("--organs: no such folder " + d.string());
  }
  const std::vector<fs::path> shared = default_organ_dirs();
  if (dirs.empty()) dirs = shared;

  // Instruments: hook-mesh is left out when no folder holds its file. The probe motions run with
  // every selected instrument but the grasper (with the grasper when it is the only one);
  // grasp-lift always with the grasper.
  const std::vector<std::string> known_instruments = suite_instrument_names();
  std::vector<fs::path> instrument_dirs = dirs;
  instrument_dirs.insert(instrument_dirs.end(), shared.begin(), shared.end());
  std::vector<SuiteInstrument> instruments;
  std::vector<std::size_t> pushers;
  bool grasper_selected = false;
  for (const std::string& name : instrument_names) {
    if (std::find(known_instruments.begin(), known_instruments.end(), name) == known_instruments.end())
      throw Error("--instruments: unknown instrument \"" + name + "\" (known: " + joined(known_instruments) + ")");
    if (name == "grasper") {
      grasper_selected = true;
      continue;
    }
    std::optional<SuiteInstrument> tool = suite_instrument(name, instrument_dirs);
    if (!tool) continue;  // hook-mesh without ../shared
    pushers.push_back(instruments.size());
    instruments.push_back(std::move(*tool));
  }
  const std::size_t grasper = instruments.size();
  instruments.push_back(*suite_instrument("grasper"));
  if (pushers.empty() && grasper_selected) pushers.push_back(grasper);

  std::vector<SuiteOrgan> organs;
  if (a.quick) {
    std::vector<SuiteOrgan> family = generated_organs(a.seed);
    organs.push_back(std::move(family.front()));
  } else {
    for (const fs::path& d : dirs)
      for (SuiteOrgan& o : organs_in(d, "shared")) organs.push_back(std::move(o));
    if (!a.no_generated)
      for (SuiteOrgan& o : generated_organs(a.seed)) organs.push_back(std::move(o));
  }
  if (organs.empty()) throw Error("no organs (give --organs DIR or drop --no-generated)");

  // organ × material × instrument × motion × solver; grasp-lift with the grasper after the
  // instruments; the rest check (light-stiff, first instrument) after the materials.
  std::vector<SuiteCase> cases;
  const bool rest = std::find(motions.begin(), motions.end(), SuiteMotion::kRest) != motions.end();
  const bool grasp = std::find(motions.begin(), motions.end(), SuiteMotion::kGraspLift) != motions.end();
  const bool probe_motions = std::any_of(motions.begin(), motions.end(), [](SuiteMotion m) {
    return m != SuiteMotion::kRest && m != SuiteMotion::kGraspLift;
  });
  if (probe_motions && pushers.empty())
    throw Error("--instruments: none available for the probe motions (hook-mesh needs " +
                std::string(kSuiteHookMeshFile) + " in ../shared/data/meshes or an --organs folder)");
  for (std::size_t o = 0; o < organs.size(); ++o) {
    for (const std::string& material : material_names) {
      for (const std::size_t i : pushers)
        for (const SuiteMotion m : motions) {
          if (m == SuiteMotion::kRest || m == SuiteMotion::kGraspLift) continue;
          for (std::size_t s = 0; s < solvers.size(); ++s) cases.push_back({o, material, i, m, s});
        }
      if (grasp)
        for (std::size_t s = 0; s < solvers.size(); ++s)
          cases.push_back({o, material, grasper, SuiteMotion::kGraspLift, s});
    }
    if (rest)
      for (std::size_t s = 0; s < solvers.size(); ++s)
        cases.push_back({o, kSuiteRestMaterial, pushers.empty() ? grasper : pushers.front(), SuiteMotion::kRest, s});
  }

  const fs::path out = a.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error("cannot create " + out.string() + ": " + ec.message());
  const auto start = std::chrono::steady_clock::now();
  std::vector<SuiteRun> runs;
  for (const SuiteCase& c : cases) {
    const SuiteOrgan& organ = organs[c.organ];
    runs.push_back(run_suite_case(organ, c.motion, suite_material(c.material, organ), instruments[c.instrument],
                                  solvers[c.solver]));
    const SuiteRun& r = runs.back();
    std::cout << "[" << runs.size() << "/" << cases.size() << "] " << r.organ << " (" << r.triangles << " T) "
              << r.material << " " << r.instrument << " " << r.motion << " " << r.solver << ": step "
              << fixed(r.step_median_us, 0) << "/" << fixed(r.step_p99_us, 0) << " us, CG "
              << fixed(r.cg_mean_contact, 1) << ", substeps " << r.substeps_max << ", error "
              << sci(r.constraint_error_max) << ", pen p99 " << fixed(r.penetration_p99 * 1e3, 3) << " max "
              << fixed(r.penetration_max * 1e3, 3) << " mm, tunnel " << r.tunneling
              << (r.rest ? ", energy drift " + drift_text(r) : "") << (r.stable ? "" : " UNSTABLE") << std::endl;
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
      "robustness",
      "Every organ x material x instrument x motion x solver: step time, CG iterations, substeps, constraint "
      "error, penetration, tunneling, energy drift at rest");
  cmd->add_option("--organs", a->organs, "Folder(s) of organ meshes (default: ../shared/data/meshes when present)");
  cmd->add_option("--out", a->out, "Output folder (robustness.csv, robustness.md, SVG plots)")->capture_default_str();
  cmd->add_option("--solvers,--methods", a->solvers,
                  "Solvers: xpbd (contact inside the solver) or a response method on implicit Euler: sdf project "
                  "obb primitive normal (default: xpbd sdf)");
  cmd->add_option("--materials", a->materials,
                  "Materials: light-soft medium heavy-stiff light-stiff preset (default: light-soft medium "
                  "heavy-stiff; the rest check always uses light-stiff)");
  cmd->add_option("--instruments", a->instruments,
                  "Instruments: hook hook-mesh grasper probe10 (default: all; hook-mesh only where "
                  "../shared/data/meshes has it; grasp-lift always uses the grasper)");
  cmd->add_option("--motions", a->motions,
                  "Motions (default: press slide poke-0.2 poke-1 poke-2 deep-press grasp-lift rest)");
  cmd->add_option("--seed", a->seed, "Seed of the generated organ family")->capture_default_str();
  cmd->add_flag("--no-generated", a->no_generated, "Leave out the generated organ family");
  cmd->add_flag("--quick", a->quick,
                "One small generated organ; light-soft and heavy-stiff, hook, press and poke-1, xpbd and sdf "
                "(for CI; lists given alongside replace these)");
  cmd->callback([a] { run_robustness(*a); });
}

}  // namespace trocar::cli
