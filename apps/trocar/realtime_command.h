#pragma once
// `trocar run SCENE --realtime`, `trocar replay RECORDING`, `trocar plot timing RECORDING`: the
// real-time runtime from the command line (docs/runtime.md).
#include <CLI/CLI.hpp>
#include <string>

namespace trocar::cli {

/// Options of `trocar run --realtime`.
struct RealtimeOptions {
  std::string scene;
  double duration = -1;      ///< wall-clock seconds (default: the scene's duration)
  double rate_hz = 1000;     ///< haptic rate
  bool lockstep = false;     ///< physics inside the haptic tick
  bool metrics = false;      ///< exact penetration metrics (off in real time by default)
  std::string method;        ///< response method override
  std::string report;        ///< JSON report path
  std::string record;        ///< binary session recording path
  bool quiet = false;
};

/// Runs a scene on the runtime and writes the report with its `haptic` section.
void run_realtime(const RealtimeOptions& options);

/// Adds the `replay` and `plot` subcommands.
void add_replay_command(CLI::App& app, int& exit_code);
void add_plot_command(CLI::App& app, int& exit_code);
/// Adds `trocar study multirate` (the multirate fidelity measurement) under `study`.
void add_multirate_command(CLI::App& study);

}  // namespace trocar::cli
