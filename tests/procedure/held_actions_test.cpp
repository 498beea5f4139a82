// The held actions: the electrode's pedal and a suction-irrigator's two trumpet valves. A device's
// button levels become presses and, on release, the matching off; applied, they open and shut the
// valves of the port's instrument in the body; scripted, each on is held until its off.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "trocar/core/error.h"
#include "trocar/procedure/actions.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

// A cannula shares the "left" port with a hook (no valves); a second cannula and a grasper (no
// "suction" key) have ports of their own. A small ball, out of their way.
std::string valves_scene(const std::string& events = "[]") {
  return R"({"schema": 1, "timestep": 0.001,
 "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.01, "subdivisions": 1},
              "material": {"preset": "liver"}}],
 "instruments": [
  {"name": "cannula", "port": "left", "mesh": {"generate": "suction-irrigator", "segments": 8}, "suction": true,
   "motion": {"keyframes": [{"t": 0, "position": [0.05, 0, 0.05]}]}},
  {"name": "hook", "port": "left", "mesh": {"generate": "hook-probe"}},
  {"name": "solo", "mesh": {"generate": "suction-irrigator", "segments": 8}, "suction": {"irrigation_flow": 0},
   "motion": {"keyframes": [{"t": 0, "position": [-0.05, 0, 0.05]}]}},
  {"name": "grasper", "mesh": {"generate": "grasper"}, "motion": {"keyframes": [{"t": 0, "position": [0, 0.05, 0.05]}]}}],
 "events": )" + events + "}";
}

TEST(HeldActions, ButtonLevelsGiveThePressAndOnReleaseTheOff) {
  // Button i+1 = action bit i: the pedal is button 3, suction 5, irrigation 7.
  EXPECT_EQ(kActionEnergyOn << 1, 1u << 3);
  EXPECT_EQ(kActionSuctionOn << 1, 1u << 5);
  EXPECT_EQ(kActionIrrigateOn << 1, 1u << 7);
  const std::uint32_t held[3][2] = {{kActionEnergyOn, kActionEnergyOff},
                                    {kActionSuctionOn, kActionSuctionOff},
                                    {kActionIrrigateOn, kActionIrrigateOff}};
  for (const auto& [on, off] : held) {
    EXPECT_EQ(button_actions(0, on), on);          // pressed
    EXPECT_EQ(button_actions(on, on), 0u);         // held: nothing new
    EXPECT_EQ(button_actions(on, 0), off);         // released
    EXPECT_EQ(button_actions(0, off), 0u);         // an off is no button
    EXPECT_EQ(button_actions(on | kActionFire, kActionFire), off);  // fire held on, not pressed again
  }
  // All three at once, and let go together; a fire press beside them.
  EXPECT_EQ(button_actions(0, kHeldActions | kActionFire), 0b01010101u);
  EXPECT_EQ(button_actions(kHeldActions, 0), 0b10101000u);
  // Suction let go while irrigation is pressed: one off, one on.
  EXPECT_EQ(button_actions(kActionSuctionOn, kActionIrrigateOn), kActionSuctionOff | kActionIrrigateOn);
  EXPECT_EQ(action_from_name("suction_on"), kActionSuctionOn);
  EXPECT_EQ(action_from_name("suction_off"), kActionSuctionOff);
  EXPECT_EQ(action_from_name("irrigate_on"), kActionIrrigateOn);
  EXPECT_EQ(action_from_name("irrigate_off"), kActionIrrigateOff);
  EXPECT_EQ(action_from_name("suction"), 0u);
}

TEST(HeldActions, ValvesOpenAndShutOnThePortsInstrumentInTheBody) {
  Scene scene = parse_scene(valves_scene(), "valves.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  ASSERT_EQ(sim.active_in_port(1), 0u);
  // Pressed for the hook waiting outside, it opens the cannula: the port's instrument in the body.
  apply_actions(sim, 1, kActionSuctionOn, nullptr);
  EXPECT_TRUE(sim.suction_on(0));
  EXPECT_FALSE(sim.suction_on(1));
  apply_actions(sim, 0, kActionIrrigateOn, nullptr);
  EXPECT_TRUE(sim.irrigation_on(0));
  apply_actions(sim, 0, kActionSuctionOff, nullptr);
  EXPECT_FALSE(sim.suction_on(0));
  EXPECT_TRUE(sim.irrigation_on(0));  // the other valve stays open
  apply_actions(sim, 0, kActionIrrigateOff, nullptr);
  EXPECT_FALSE(sim.irrigation_on(0));
  // "solo" has suction but its irrigation flow is 0; the grasper has no "suction": shut.
  apply_actions(sim, 2, kActionSuctionOn | kActionIrrigateOn, nullptr);
  EXPECT_TRUE(sim.suction_on(2));
  EXPECT_FALSE(sim.irrigation_on(2));
  apply_actions(sim, 3, kActionSuctionOn | kActionIrrigateOn, nullptr);
  EXPECT_FALSE(sim.suction_on(3));
  EXPECT_FALSE(sim.irrigation_on(3));
  // An exchange withdraws the cannula with both valves shut; the hook it brings in has none.
  apply_actions(sim, 0, kActionSuctionOn | kActionIrrigateOn | kActionEnergyOn, nullptr);
  ASSERT_TRUE(sim.suction_on(0) && sim.irrigation_on(0) && sim.energy_on(0));
  apply_actions(sim, 0, kActionExchange, nullptr);
  EXPECT_FALSE(sim.suction_on(0));
  EXPECT_FALSE(sim.irrigation_on(0));
  EXPECT_FALSE(sim.energy_on(0));
  EXPECT_EQ(sim.active_in_port(0), 1u);
  apply_actions(sim, 0, kActionSuctionOn | kActionIrrigateOn, nullptr);
  EXPECT_FALSE(sim.suction_on(0) || sim.suction_on(1) || sim.irrigation_on(0) || sim.irrigation_on(1));
  // Alone in its port an exchange changes nothing, but the valve is shut all the same.
  EXPECT_TRUE(sim.suction_on(2));
  apply_actions(sim, 2, kActionExchange, nullptr);
  EXPECT_FALSE(sim.suction_on(2));
  EXPECT_EQ(sim.active_in_port(2), 2u);
}

TEST(HeldActions, ScriptedOnsAreHeldUntilTheInstrumentsNextMatchingOff) {
  const Scene scene = parse_scene(valves_scene(R"([
    {"t": 0.1, "action": "suction_on", "instrument": "cannula"},
    {"t": 0.2, "action": "irrigate_on", "instrument": "cannula"},
    {"t": 0.25, "action": "suction_off", "instrument": "solo"},
    {"t": 0.3, "action": "irrigate_off", "instrument": "cannula"},
    {"t": 0.4, "action": "suction_off", "instrument": "cannula"},
    {"t": 0.5, "action": "suction_off", "instrument": "cannula"},
    {"t": 0.6, "action": "irrigate_on", "instrument": "solo"}])"), "valves.json", ".");
  ASSERT_EQ(scene.actions.size(), 7u);
  EXPECT_EQ(scene.actions[0].action, kActionSuctionOn);
  EXPECT_EQ(scene.actions[3].action, kActionIrrigateOff);
  // The offs are releases, not presses: two presses for the cannula, one for solo.
  const auto& cannula = scene.devices[0].presses;
  ASSERT_EQ(cannula.size(), 2u);
  EXPECT_EQ(cannula[0].t, 0.1);
  EXPECT_EQ(cannula[0].buttons, 1u << 5);  // button 5
  EXPECT_EQ(cannula[0].until, 0.4);        // not solo's suction_off, not irrigate_off
  EXPECT_EQ(cannula[1].t, 0.2);
  EXPECT_EQ(cannula[1].buttons, 1u << 7);  // button 7
  EXPECT_EQ(cannula[1].until, 0.3);
  const auto& solo = scene.devices[2].presses;
  ASSERT_EQ(solo.size(), 1u);
  EXPECT_EQ(solo[0].buttons, 1u << 7);
  EXPECT_EQ(solo[0].until, std::numeric_limits<double>::infinity());  // no off: held to the end
  EXPECT_TRUE(scene.devices[1].presses.empty());
}

TEST(HeldActions, AnUnknownActionListsTheValves) {
  try {
    parse_scene(valves_scene(R"([{"t": 0, "action": "suck", "instrument": "cannula"}])"), "valves.json", ".");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "valves.json: events[0].action: unknown action \"suck\" (known: fire, exchange, energy_on, energy_off, "
              "suction_on, suction_off, irrigate_on, irrigate_off)");
  }
}

}  // namespace
}  // namespace trocar
