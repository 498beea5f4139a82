#pragma once
// Electrosurgery and bleeding in `trocar run`'s JSON report (docs/electrosurgery.md, "Report").
#include <nlohmann/json.hpp>

#include "trocar/sim/simulation.h"

namespace trocar::cli {

/// {"energy_J", "tissues": [{"name", "energy_J", "coagulated_mm2", "cut_mm2", "cut_triangles"}],
///  "blood_loss_ml", "wounds": [{"tissue", "vessel_mm", "artery", "opened_s", "state", "bled_ml",
///  "time_to_haemostasis_s" (null while bleeding)}]}; tissues only where an electrode put energy.
nlohmann::json electrosurgery_report(const Simulation& sim);

/// True when the scene can burn or bleed (an electrode, or a bleeding tissue): the report has the
/// section then.
bool has_electrosurgery(const Simulation& sim);

}  // namespace trocar::cli
