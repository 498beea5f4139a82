#pragma once
// `trocar plot timing RECORDING`: time per iteration of each module over a recorded session.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `plot` subcommand and its `timing` plot.
void add_plot_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
