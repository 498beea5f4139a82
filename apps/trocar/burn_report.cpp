#include "burn_report.h"

namespace trocar::cli {
namespace {

const char* wound_state_name(WoundState s) {
  switch (s) {
    case WoundState::kBleeding: return "bleeding";
    case WoundState::kNeedsClip: return "needs clip";
    case WoundState::kSealed: return "sealed";
    case WoundState::kClipped: return "clipped";
  }
  return "bleeding";
}

}  // namespace

bool has_electrosurgery(const Simulation& sim) {
  for (const InstrumentBody& body : sim.world().instruments)
    if (body.electrode.power > 0) return true;
  return sim.bleeding().tissues() > 0;
}

nlohmann::json electrosurgery_report(const Simulation& sim) {
  const World& world = sim.world();
  nlohmann::json tissues = nlohmann::json::array();
  double energy = 0;
  for (std::size_t t = 0; t < world.tissues.size(); ++t) {
    const BurnTally b = sim.burn_tally(t);
    energy += b.energy;
    if (!(b.energy > 0)) continue;
    tissues.push_back({{"name", world.tissues[t]->name},
                       {"energy_J", b.energy},
                       {"coagulated_mm2", 1e6 * b.coagulated_area},
                       {"cut_mm2", 1e6 * b.cut_area},
                       {"cut_triangles", b.cut_triangles}});
  }
  nlohmann::json wounds = nlohmann::json::array();
  const Bleeding& bleeding = sim.bleeding();
  for (std::size_t w = 0; w < bleeding.wounds().size(); ++w) {
    const Bleeding::Wound& wound = bleeding.wounds()[w];
    const std::optional<Real> took = bleeding.time_to_haemostasis(w);
    wounds.push_back({{"tissue", world.tissues[sim.bleeding_tissue(wound.tissue)]->name},
                      {"vessel_mm", 1e3 * wound.vessel.diameter},
                      {"artery", wound.vessel.artery},
                      {"opened_s", wound.opened},
                      {"state", wound_state_name(wound.state)},
                      {"bled_ml", 1e6 * wound.emitted},
                      {"time_to_haemostasis_s", took ? nlohmann::json(*took) : nlohmann::json(nullptr)}});
  }
  return {{"energy_J", energy}, {"tissues", tissues}, {"blood_loss_ml", 1e6 * bleeding.emitted()}, {"wounds", wounds}};
}

}  // namespace trocar::cli
