#pragma once
// `trocar study penetration`: residual penetration and tunneling vs speed × response method ×
// detection period (docs/penetration-study.md; the study itself is trocar/study/penetration.h).
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds `penetration` under the `study` subcommand.
void add_penetration_command(CLI::App& study);

}  // namespace trocar::cli
