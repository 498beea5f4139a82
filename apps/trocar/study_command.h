#pragma once
// `trocar study penetration`: residual penetration and tunneling against instrument speed, for
// every response method and detection period, on the shipped stab and press scenes.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `study` subcommand and its `penetration` subcommand. Writes penetration.csv,
/// summary.md and (when gnuplot is on the PATH) SVG plots into --out; throws trocar::Error on
/// failure (missing scene, unwritable folder).
void add_study_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
