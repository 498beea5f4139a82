#include "trocar/procedure/actions.h"

#include <algorithm>

#include "trocar/sim/simulation.h"

namespace trocar {

std::uint32_t action_from_name(const std::string& name) {
  if (name == "fire") return kActionFire;
  if (name == "exchange") return kActionExchange;
  return 0;
}

ActionScript::ActionScript(std::vector<ScriptedAction> actions) : actions_(std::move(actions)) {
  std::stable_sort(actions_.begin(), actions_.end(),
                   [](const ScriptedAction& a, const ScriptedAction& b) { return a.t < b.t; });
}

void apply_actions(Simulation& sim, std::size_t instrument, std::uint32_t bits, ActionHandler* handler) {
  if (instrument >= sim.world().instruments.size()) return;
  if ((bits & kActionFire) && handler != nullptr) handler->fire(sim, sim.active_in_port(instrument));
  if (bits & kActionExchange) sim.exchange(instrument);
}

}  // namespace trocar
