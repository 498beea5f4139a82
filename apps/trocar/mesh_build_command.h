#pragma once
// `trocar mesh build`, `trocar mesh labels` and `trocar mesh phantom`: the offline modelling
// pipeline (src/trocar/modelling/). Without the modelling module they say how to get it.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds build, labels and phantom to the `mesh` subcommand.
void add_mesh_build_commands(CLI::App& mesh, int& exit_code);

/// Lets scenes name volumes (`"mesh": {"build": ...}`) when the modelling module is built.
void install_scene_mesh_builder();

}  // namespace trocar::cli
