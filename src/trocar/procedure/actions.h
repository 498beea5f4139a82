#pragma once
/// What a trainee does besides moving: fire the tacker, exchange the instrument in a port, press
/// and release the electrode's pedal or a suction-irrigator's two trumpet valves. From a
/// device's buttons, the viewer's keys, a scene's scripted "events", or a recording; one bit set
/// each, applied between steps (docs/procedure.md, "Actions").
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// Action bits (a device's buttons map onto them: docs/devices.md).
enum ActionBit : std::uint32_t {
  kActionFire = 1u << 0,        ///< fire the tacker (or the clip applier) in this instrument's port
  kActionExchange = 1u << 1,    ///< exchange the instrument in this instrument's port
  /// The electrode's pedal pressed (docs/electrosurgery.md). As a device's button (button 3) the
  /// bit is the pedal's level, held while it is down; recorded and scripted it is the press.
  kActionEnergyOn = 1u << 2,
  kActionEnergyOff = 1u << 3,   ///< the pedal released (recorded and scripted; no button)
  /// A suction-irrigator's valves (electrosurgery/suction.h), held like the pedal: suction is
  /// button 5, irrigation button 7; each Off bit is its release (recorded and scripted; no button).
  kActionSuctionOn = 1u << 4,
  kActionSuctionOff = 1u << 5,
  kActionIrrigateOn = 1u << 6,
  kActionIrrigateOff = 1u << 7,
};

/// The held actions (a level while the button is down), each with its release bit one above it.
inline constexpr std::uint32_t kHeldActions = kActionEnergyOn | kActionSuctionOn | kActionIrrigateOn;

/// The bits a device's buttons carry as levels (button i+1 = bit i): fire, exchange, the pedal,
/// suction, irrigation.
inline constexpr std::uint32_t kButtonActions = kActionFire | kActionExchange | kHeldActions;

/// What a step applies for a device whose button levels went from `before` to `now`: the presses
/// of fire, exchange, the pedal and the valves, and each held action's release as its Off bit
/// (On << 1).
inline std::uint32_t button_actions(std::uint32_t before, std::uint32_t now) {
  const std::uint32_t pressed = now & ~before & kButtonActions;
  const std::uint32_t released = before & ~now & kHeldActions;
  return pressed | (released << 1);
}

/// "fire" / "exchange" / "energy_on" / "energy_off" / "suction_on" / "suction_off" /
/// "irrigate_on" / "irrigate_off" → its bit; 0 for any other name.
std::uint32_t action_from_name(const std::string& name);

/// One scripted action (scene "events": {"t", "action", "instrument"}).
struct ScriptedAction {
  Real t = 0;                  ///< s: applied before the first step that ends after t
  std::uint32_t action = 0;    ///< one ActionBit
  std::size_t instrument = 0;  ///< the instrument (its port) it acts on
};

/// A scene's scripted actions, played in time order.
class ActionScript {
 public:
  ActionScript() = default;
  /// Sorts by time, keeping the scene's order among equal times.
  explicit ActionScript(std::vector<ScriptedAction> actions);

  /// Calls on_action(instrument, bit) for every action not yet played with t < time (the end of
  /// the step about to run), in order. No allocation.
  template <typename OnAction>
  void play_before(Real time, OnAction&& on_action) {
    while (next_ < actions_.size() && actions_[next_].t < time) {
      const ScriptedAction& a = actions_[next_++];
      on_action(a.instrument, a.action);
    }
  }
  std::size_t played() const { return next_; }                ///< actions played so far
  const std::vector<ScriptedAction>& actions() const { return actions_; }

 private:
  std::vector<ScriptedAction> actions_;
  std::size_t next_ = 0;
};

class Simulation;

/// Carries out the actions the simulation itself does not: firing the tacker (the procedure).
class ActionHandler {
 public:
  virtual ~ActionHandler() = default;
  /// Fire the tacker `instrument` (the instrument in the body at its port).
  virtual void fire(Simulation& sim, std::size_t instrument) = 0;
};

/// Applies action bits on instrument i's port: exchange → Simulation::exchange(i) (the pedal up
/// and the valves shut first); fire → handler->fire(sim, the port's instrument in the body), when
/// a handler is given; the pedal and the valves → set_energy, set_suction, set_irrigation on it.
void apply_actions(Simulation& sim, std::size_t instrument, std::uint32_t bits, ActionHandler* handler);

/// Rising edges: the bits set in `now` that were clear in `before`.
inline std::uint32_t pressed_bits(std::uint32_t before, std::uint32_t now) { return now & ~before; }

}  // namespace trocar
