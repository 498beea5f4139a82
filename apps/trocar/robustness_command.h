#pragma once
// `trocar study robustness`: every organ × motion × response method (docs/robustness.md).
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds `robustness` under the `study` subcommand. Writes robustness.csv, robustness.md and
/// (when gnuplot is on the PATH) SVG plots into --out; throws trocar::Error on failure.
void add_robustness_command(CLI::App& study);

}  // namespace trocar::cli
