#include "trocar/scene/action_keys.h"

namespace trocar {

std::vector<ScriptedAction> read_actions(const JsonReader& list, const World& world) {
  std::vector<ScriptedAction> out;
  for (std::size_t k = 0; k < list.array_size(); ++k) {
    const JsonReader e = list.at(k);
    e.expect_keys({"t", "action", "instrument"});
    ScriptedAction a;
    a.t = e.at("t").number_at_least(0);
    const JsonReader action = e.at("action");
    a.action = action_from_name(action.string());
    if (a.action == 0)
      action.fail("unknown action \"" + action.string() +
                  "\" (known: fire, exchange, energy_on, energy_off, suction_on, suction_off, irrigate_on, irrigate_off)");
    const JsonReader who = e.at("instrument");
    const std::string name = who.string();
    bool found = false;
    for (std::size_t i = 0; i < world.instruments.size() && !found; ++i)
      if (world.instruments[i].name == name) {
        a.instrument = i;
        found = true;
      }
    if (!found) who.fail("no instrument named \"" + name + "\"");
    out.push_back(a);
  }
  return out;
}

}  // namespace trocar
