#pragma once
// `trocar view SCENE`: the interactive viewer (src/trocar/render/viewer.h), when built.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `view` subcommand (a clear error when this build has no viewer).
void add_view_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
