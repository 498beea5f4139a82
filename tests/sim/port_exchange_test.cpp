// Instrument exchange through a port: the second instrument of a port waits outside the body,
// an exchange withdraws the one inside (its jaws let go first) and inserts the next at its pose;
// scripted actions play in time order.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "trocar/core/error.h"
#include "trocar/procedure/actions.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

// A grasper closes on a sheet (2 mm cells, its x < −25 mm edge fixed) at 0.3 s and lifts it by
// 2 cm until 0.8 s; a hook shares its port, another has a port of its own. `events` is spliced
// into the scene.
std::string lift_scene(const std::string& events) {
  return R"({"schema": 1, "name": "lift", "timestep": 0.001, "gravity": [0, 0, -9.81],
 "tissues": [{"name": "sheet", "mesh": {"generate": "sheet", "width": 0.06, "height": 0.06, "nx": 30, "ny": 30},
   "material": {"preset": "peritoneum"},
   "fixed": {"inside_box": {"min": [-1, -1, -1], "max": [-0.025, 1, 1]}}}],
 "instruments": [
  {"name": "grasper", "port": "right", "mesh": {"generate": "grasper", "shaft_length": 0.15}, "top_vertex": "auto",
   "jaw_triangles": [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23],
   "motion": {"keyframes": [{"t": 0.0, "position": [0.01, 0.0005, -0.005], "jaw": 0},
                            {"t": 0.1, "position": [0.01, 0.0005, -0.005], "jaw": 1},
                            {"t": 0.6, "position": [0.01, 0.0005, 0.015], "jaw": 1}]}},
  {"name": "other", "port": "right", "mesh": {"generate": "hook-probe"}},
  {"name": "alone", "mesh": {"generate": "hook-probe"}, "motion": {"keyframes": [{"t": 0, "position": [0.3, 0, 0.3]}]}}],
 "events": )" + events + "}";
}

Real sheet_top(const Simulation& sim) {
  Real top = -1;
  for (const Vec3& x : sim.world().tissues[0]->state.positions) top = std::max(top, x.z());
  return top;
}

TEST(PortExchange, TheSecondInstrumentOfAPortWaitsOutsideTheBody) {
  Scene scene = parse_scene(lift_scene("[]"), "lift.json", ".");
  EXPECT_EQ(scene.world.instruments[1].port, "right");
  EXPECT_EQ(scene.world.instruments[0].tool, "grasper");
  EXPECT_EQ(scene.world.instruments[1].tool, "hook-probe");
  Simulation sim(std::move(scene.world), scene.settings);
  EXPECT_FALSE(sim.parked(0));
  EXPECT_TRUE(sim.parked(1));
  EXPECT_FALSE(sim.parked(2));
  EXPECT_EQ(sim.active_in_port(1), 0u);
  EXPECT_EQ(sim.active_in_port(2), 2u);
  EXPECT_GT(sim.world().instruments[1].instrument.pose().translation.z(), 50.0);  // far from the 16 cm scene
  // A port of its own: an exchange changes nothing.
  EXPECT_EQ(sim.exchange(2), 2u);
  EXPECT_FALSE(sim.parked(2));
}

TEST(PortExchange, ExchangeLetsGoThenInsertsTheNextInstrumentAtTheSamePose) {
  Scene scene = parse_scene(lift_scene("[]"), "lift.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  const Real dt = 0.001;
  const Real rest_top = sheet_top(sim);
  for (int k = 0; k < 700; ++k) sim.step(dt);
  const Real lifted_top = sheet_top(sim);
  ASSERT_GT(lifted_top - rest_top, 0.01) << "the grasper lifts the sheet (it holds it)";
  const Pose held = sim.world().instruments[0].instrument.pose();

  EXPECT_EQ(sim.exchange(0), 1u);
  EXPECT_EQ(sim.active_in_port(0), 1u);
  EXPECT_EQ(sim.exchange(0), 1u) << "a second press during the exchange does nothing";
  sim.step(dt);  // the grasper stays and opens: it lets go
  EXPECT_EQ(sim.world().instruments[0].instrument.jaw(), 0.0);
  EXPECT_TRUE((sim.world().instruments[0].instrument.pose().translation - held.translation).norm() < 1e-12);
  EXPECT_GT(sim.world().instruments[1].instrument.pose().translation.z(), 50.0) << "not in yet";
  sim.step(dt);  // it leaves; the other comes in where it was
  EXPECT_TRUE(sim.parked(0));
  EXPECT_FALSE(sim.parked(1));
  EXPECT_LT((sim.world().instruments[1].instrument.pose().translation - held.translation).norm(), 1e-12);
  EXPECT_GT(sim.world().instruments[0].instrument.pose().translation.z(), 50.0);
  for (int k = 0; k < 500; ++k) sim.step(dt);
  EXPECT_LT(sheet_top(sim) - rest_top, 0.3 * (lifted_top - rest_top)) << "let go: the sheet falls back";
  EXPECT_TRUE(sim.metrics().finite);

  // And back: the grasper returns at the other's pose.
  const Pose other = sim.world().instruments[1].instrument.pose();
  EXPECT_EQ(sim.exchange(1), 0u);
  sim.step(dt);
  EXPECT_FALSE(sim.parked(0));
  EXPECT_LT((sim.world().instruments[0].instrument.pose().translation - other.translation).norm(), 1e-12);
}

TEST(PortExchange, JawsHoldNothingOfATissueThatIsNotGraspable) {
  const auto lift = [](const std::string& graspable) {
    std::string text = lift_scene("[]");
    const std::string key = R"("material": {"preset": "peritoneum"},)";
    text.replace(text.find(key), key.size(), key + graspable);
    Scene scene = parse_scene(text, "lift.json", ".");
    Simulation sim(std::move(scene.world), scene.settings);
    const Real rest_top = sheet_top(sim);
    for (int k = 0; k < 700; ++k) sim.step(0.001);
    EXPECT_TRUE(sim.metrics().finite);
    return std::pair{sim.response(0).held_vertices(0), sheet_top(sim) - rest_top};
  };
  const auto [held, lifted] = lift("");
  const auto [held_not, lifted_not] = lift(R"("graspable": false,)");
  EXPECT_GT(held, 0u);
  EXPECT_GT(lifted, 0.01);
  EXPECT_EQ(held_not, 0u);
  EXPECT_LT(lifted_not, 0.003) << "the closed jaws only push it as they rise through it";
}

TEST(PortExchange, ACommandedPortStaysCommandedAfterTheExchange) {
  Scene scene = parse_scene(lift_scene("[]"), "lift.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  Pose device;
  device.translation = Vec3(0.05, 0.0, 0.08);
  sim.place_instrument(0, device, 0);
  sim.step(0.001);
  sim.exchange(0);
  sim.step(0.001);
  EXPECT_TRUE(sim.instrument_commanded(1));
  EXPECT_FALSE(sim.instrument_commanded(0));
  EXPECT_LT((sim.world().instruments[1].instrument.pose().translation - device.translation).norm(), 1e-12);
}

TEST(ActionScript, PlaysInTimeOrderBeforeTheStepThatPassesThem) {
  Scene scene = parse_scene(lift_scene(R"([{"t": 0.0105, "action": "exchange", "instrument": "other"},
    {"t": 0.002, "action": "fire", "instrument": "grasper"}])"), "lift.json", ".");
  ASSERT_EQ(scene.actions.size(), 2u);
  ActionScript script(scene.actions);
  std::vector<std::pair<std::size_t, std::uint32_t>> played;
  std::vector<int> at_step;
  for (int k = 1; k <= 20; ++k)
    script.play_before(k * 0.001, [&](std::size_t i, std::uint32_t bit) {
      played.emplace_back(i, bit);
      at_step.push_back(k);
    });
  ASSERT_EQ(played.size(), 2u);
  EXPECT_EQ(played[0], std::make_pair(std::size_t{0}, std::uint32_t{kActionFire}));
  EXPECT_EQ(at_step[0], 3);  // 0.002 < 0.003: before the third step
  EXPECT_EQ(played[1], std::make_pair(std::size_t{1}, std::uint32_t{kActionExchange}));
  EXPECT_EQ(at_step[1], 11);
  EXPECT_EQ(pressed_bits(0b01, 0b11), 0b10u);
  EXPECT_EQ(pressed_bits(0b11, 0b01), 0u);
}

TEST(ActionScript, BadEventsNameTheKey) {
  auto error_of = [](const std::string& events) {
    try {
      parse_scene(lift_scene(events), "lift.json", ".");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(R"([{"t": 1, "action": "staple", "instrument": "grasper"}])").find("unknown action"),
            std::string::npos);
  EXPECT_NE(error_of(R"([{"t": 1, "action": "fire", "instrument": "nobody"}])").find("no instrument named"),
            std::string::npos);
  EXPECT_NE(error_of(R"([{"t": -1, "action": "fire", "instrument": "grasper"}])").find("events"), std::string::npos);
}

}  // namespace
}  // namespace trocar
