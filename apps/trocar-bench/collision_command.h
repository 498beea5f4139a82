#pragma once
// `trocar-bench collision` (also reached as `trocar bench collision`): trocar's collision detection
// against FCL and Bullet on two meshes (docs/collision-bench.md).
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `collision` subcommand. The handler runs from a CLI11 callback and throws
/// trocar::Error on failure (unreadable or empty mesh, naming the file); `exit_code` receives 1
/// when the methods disagree on a frame's pair count.
void add_collision_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
