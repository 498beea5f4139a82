#pragma once
// `trocar replay RECORDING`: redo a recorded real-time session in lock-step and compare its
// state hash (docs/recording.md).
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `replay` subcommand (exit code 3 when the hash differs).
void add_replay_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
