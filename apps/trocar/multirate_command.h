#pragma once
// `trocar study multirate`: the multirate fidelity measurement (docs/runtime.md; the study itself
// is trocar/study/fidelity.h).
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds `multirate` under the `study` subcommand.
void add_multirate_command(CLI::App& study);

}  // namespace trocar::cli
