#pragma once
// `trocar run SCENE --realtime`: a scene on the real-time runtime (docs/runtime.md).
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


}  // namespace trocar::cli
