#include "trocar/study/robustness_report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "trocar/core/error.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;

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

}  // namespace

bool write_robustness_report(const fs::path& out, const std::vector<SuiteRun>& runs, double wall_s) {
  write_csv(out / "robustness.csv", runs);
  const bool plots = write_plots(out, runs);
  write_markdown(out / "robustness.md", runs, wall_s, plots);
  return plots;
}

std::string robustness_run_line(const SuiteRun& r) {
  std::ostringstream s;
  s << r.organ << " (" << r.triangles << " T) " << r.material << " " << r.instrument << " " << r.motion << " "
    << r.solver << ": step " << fixed(r.step_median_us, 0) << "/" << fixed(r.step_p99_us, 0) << " us, CG "
    << fixed(r.cg_mean_contact, 1) << ", substeps " << r.substeps_max << ", error " << sci(r.constraint_error_max)
    << ", pen p99 " << fixed(r.penetration_p99 * 1e3, 3) << " max " << fixed(r.penetration_max * 1e3, 3)
    << " mm, tunnel " << r.tunneling << (r.rest ? ", energy drift " + drift_text(r) : "")
    << (r.stable ? "" : " UNSTABLE");
  return s.str();
}

}  // namespace trocar
