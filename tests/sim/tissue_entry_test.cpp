// A tissue that enters the body later (scene "enters_at"; docs/scene.md): it waits outside, far
// from everything and not stepped, and enters at its rest shape, at rest, at its time.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "trocar/core/error.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

std::string entry_scene(const std::string& enters_at) {
  return R"({"schema": 1, "name": "entry", "timestep": 0.001, "gravity": [0, 0, -9.81],
 "tissues": [{"name": "late", "mesh": {"generate": "sheet", "width": 0.04, "height": 0.04, "nx": 8, "ny": 8},
              "material": {"preset": "peritoneum", "k_home": 0}, "enters_at": )" +
         enters_at + R"(},
             {"name": "floor", "mesh": {"generate": "sheet", "width": 0.1, "height": 0.1, "nx": 4, "ny": 4},
              "translate": [0, 0, -1], "material": {"preset": "peritoneum"}, "fixed": {"indices": [0, 4, 20, 24]}}]})";
}

TEST(TissueEntry, ATissueWaitsOutsideUntilItsTimeThenEntersAtRestAndFalls) {
  Scene scene = parse_scene(entry_scene("0.010"), "entry.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  const TissueBody& late = *sim.world().tissues[0];
  ASSERT_TRUE(sim.tissue_waiting(0));
  EXPECT_FALSE(sim.tissue_waiting(1));
  EXPECT_GT(late.state.positions[0].x(), 500.0);  // a kilometre out: nothing reaches it
  const std::vector<Vec3> parked = late.state.positions;
  for (int k = 0; k < 9; ++k) sim.step(0.001);
  EXPECT_TRUE(sim.tissue_waiting(0));
  EXPECT_EQ(late.state.positions, parked) << "not stepped while it waits: no gravity, no drift";
  sim.step(0.001);  // t = 10 ms: it enters, then takes this step's fall
  EXPECT_FALSE(sim.tissue_waiting(0));
  for (std::size_t v = 0; v < parked.size(); ++v) {
    EXPECT_LT((late.state.positions[v] - late.settings.rest_positions[v]).norm(), 1e-4);
    EXPECT_NEAR(late.state.velocities[v].z(), -9.81e-3, 2e-3);  // one step of g from rest
  }
  for (int k = 0; k < 100; ++k) sim.step(0.001);
  // Free (no home springs) for t = 0.101 s from rest, under the preset's mass damping γ = 5/s:
  // fall = (g/γ)(t − (1 − e^(−γt))/γ) = 42.6 mm (½·g·t² would be 50.0 mm undamped).
  const Real g = 9.81, gamma = late.settings.damping, t = 0.101;
  const Real expected = g / gamma * (t - (1 - std::exp(-gamma * t)) / gamma);
  const Real fall = late.settings.rest_positions[0].z() - late.state.positions[0].z();
  EXPECT_NEAR(gamma, 5.0, 1e-12);
  EXPECT_NEAR(fall, expected, 0.001);
  EXPECT_TRUE(sim.metrics().finite);
}

TEST(TissueEntry, ANegativeTimeIsAnErrorNamingTheKey) {
  try {
    parse_scene(entry_scene("-1"), "entry.json", ".");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("enters_at"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trocar
