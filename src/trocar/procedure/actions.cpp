#include "trocar/procedure/actions.h"

#include <algorithm>

#include "trocar/sim/simulation.h"

namespace trocar {

std::uint32_t action_from_name(const std::string& name) {
  if (name == "fire") return kActionFire;
  if (name == "exchange") return kActionExchange;
  if (name == "energy_on") return kActionEnergyOn;
  if (name == "energy_off") return kActionEnergyOff;
  if (name == "suction_on") return kActionSuctionOn;
  if (name == "suction_off") return kActionSuctionOff;
  if (name == "irrigate_on") return kActionIrrigateOn;
  if (name == "irrigate_off") return kActionIrrigateOff;
  return 0;
}

ActionScript::ActionScript(std::vector<ScriptedAction> actions) : actions_(std::move(actions)) {
  std::stable_sort(actions_.begin(), actions_.end(),
                   [](const ScriptedAction& a, const ScriptedAction& b) { return a.t < b.t; });
}

void apply_actions(Simulation& sim, std::size_t instrument, std::uint32_t bits, ActionHandler* handler) {
  if (instrument >= sim.world().instruments.size()) return;
  // Fire: a clip applier clips the bleeding point between its jaws; anything else is the
  // handler's (the procedure fires a tacker).
  if (bits & kActionFire) {
    const std::size_t in_body = sim.active_in_port(instrument);
    if (sim.world().instruments[in_body].tool == "clip-applier") sim.clip_at(in_body);
    else if (handler != nullptr) handler->fire(sim, in_body);
  }
  // The pedal and the valves drive the port's instrument in the body (a valve it lacks stays
  // shut: Simulation::set_suction); an exchange takes it out with the pedal up and the valves shut.
  const std::size_t active = sim.active_in_port(instrument);
  if (bits & kActionEnergyOn) sim.set_energy(active, true);
  if (bits & kActionEnergyOff) sim.set_energy(active, false);
  if (bits & kActionSuctionOn) sim.set_suction(active, true);
  if (bits & kActionSuctionOff) sim.set_suction(active, false);
  if (bits & kActionIrrigateOn) sim.set_irrigation(active, true);
  if (bits & kActionIrrigateOff) sim.set_irrigation(active, false);
  if (bits & kActionExchange) {
    sim.set_energy(active, false);
    sim.set_suction(active, false);
    sim.set_irrigation(active, false);
    sim.exchange(instrument);
  }
}

}  // namespace trocar
