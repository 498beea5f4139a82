#pragma once
// `trocar study`: the measurements of the simulator's claims, one subcommand per study
// (penetration, robustness, multirate; each in its own file, the studies in trocar/study/).
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `study` subcommand and its studies; each throws trocar::Error on failure.
void add_study_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
