#pragma once
// `trocar bench ...`: runs the trocar-bench program beside this one (trocar measured against
// FCL and Bullet, apps/trocar-bench), so that `trocar` itself links no peer library.
#include <CLI/CLI.hpp>

namespace trocar::cli {

/// Adds the `bench` subcommand: every argument after it goes to trocar-bench. Throws
/// trocar::Error saying what to build when this build has no trocar-bench.
void add_bench_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
