#include "trocar/procedure/actions.h"

#include <algorithm>

#include "trocar/sim/simulation.h"

namespace trocar {

std::uint32_t action_from_name(const std::string& name) {
  if (name == "fire") return kActionFire;
  if (name == "exchange") return kActionExchange;
  if (name == "energy_on") return kActionEnergyOn;
  if (name == "energy_off") return kActionEnergyOff;
  return 0;
}

ActionScript::ActionScript(std::vector<ScriptedAction> actions) : actions_(std::move(actions)) {
  std::stable_sort(actions_.begin(), actions_.end(),
                   [](const ScriptedAction& a, const ScriptedAction& b) { return a.t < b.t; });
}

void apply_actions(Simulation& sim, std::size_t instrument, std::uint32_t bits, ActionHandler* handler) {
  if (instrument >= sim.world().instruments.size()) return;
  if ((bits & kActionFire) && handler != nullptr) handler->fire(sim, sim.active_in_port(instrument));
  // The pedal drives the electrode of the port's instrument in the body; an exchange takes it out
  // with the pedal up.
  if (bits & kActionEnergyOn) sim.set_energy(sim.active_in_port(instrument), true);
  if (bits & kActionEnergyOff) sim.set_energy(sim.active_in_port(instrument), false);
  if (bits & kActionExchange) {
    sim.set_energy(sim.active_in_port(instrument), false);
    sim.exchange(instrument);
  }
}

}  // namespace trocar
