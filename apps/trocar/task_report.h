#pragma once
// The task's part of `trocar run`'s output: the steps (state, time done) and the events, on stdout
// and in the JSON report (docs/procedure.md).
#include <nlohmann/json.hpp>

#include "trocar/procedure/procedure.h"

namespace trocar::cli {

/// {"name", "complete", "errors", "steps": [{"name", "state", "done_at_s", "detail"}],
///  "tacks": [...], "events": [{"time_s", "kind", "error", "place_m", "zone", "text"}]}.
nlohmann::json task_report(const Procedure& procedure);

/// The steps and the events, one line each, on stdout.
void print_task(const Procedure& procedure);

}  // namespace trocar::cli
