#pragma once
// `trocar mesh ...`: info, repair and generate.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `mesh` subcommand and its own subcommands to the program. The handlers run from
/// CLI11 callbacks and throw trocar::Error on failure; `exit_code` receives 1 when some file
/// could not be read (info goes on with the other files).
void add_mesh_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
