#pragma once
/// The robustness suite's report (docs/robustness.md): the CSV of every run, the markdown tables
/// (summary per solver, the cases against the targets) and the gnuplot script and plots.
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/study/robustness.h"

namespace trocar {

/// Writes robustness.csv, plots.gp (and, when gnuplot is on the PATH, the SVG plots) and
/// robustness.md into `out` (which must exist); `wall_s` is printed in the markdown. Returns
/// whether plots were drawn. Throws trocar::Error when a file cannot be written.
bool write_robustness_report(const std::filesystem::path& out, const std::vector<SuiteRun>& runs, double wall_s);

/// One line of a run's figures (organ, material, instrument, motion, solver, step time, CG,
/// substeps, error, penetration, tunneling, the rest check's drift, UNSTABLE), for progress output.
std::string robustness_run_line(const SuiteRun& run);

}  // namespace trocar
