#pragma once
// `trocar run SCENE`: a headless simulation, a report (docs/scene.md "`trocar run`") and a per-step
// recording.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `run` subcommand. The handler throws trocar::Error for a bad scene or option (main
/// prints it and exits 1); it writes the report and the recording to temporary files and renames
/// them at the end, so nothing partial is left behind.
void add_run_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
