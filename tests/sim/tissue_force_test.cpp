// Each tissue's share of the force on an instrument (Simulation::tissue_force): what the trainee's
// tissue-handling metrics read (docs/assessment.md). Two balls, a probe pressing the right one.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

std::string two_balls(const std::string& integrator) {
  const std::string ball = R"("mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3},
      "material": {"mass": 0.1, "k_structural": 200, "k_bending": 20, "damping": 2, "k_volume": 500, "k_home": 20},
      "fixed": {"below_plane": {"point": [0, 0, -0.015], "normal": [0, 0, 1]}}, "integrator": ")" +
                           integrator + "\"";
  return R"({"schema": 1, "name": "two-balls", "timestep": 0.001, "duration": 0.3, "gravity": [0, 0, 0],
  "tissues": [{"name": "left_ball", "translate": [-0.05, 0, 0], )" + ball + R"(},
              {"name": "right_ball", "translate": [0.05, 0, 0], )" + ball + R"(}],
  "instruments": [{"name": "probe", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05, "segments": 12, "rings": 3},
    "top_vertex": "auto",
    "motion": {"keyframes": [{"t": 0, "position": [0.05, 0, 0.04]}, {"t": 0.2, "position": [0.05, 0, 0.028]}]}}],
  "collision": {"broad_phase": "ohc", "cell_size": "auto"},
  "response": {"method": "obb", "stiffness": 200, "damping": 10, "max_force": 10}})";
}

class TissueForce : public ::testing::TestWithParam<const char*> {};

TEST_P(TissueForce, IsTheTouchedTissuesShareAndTheSharesSumToTheInstrumentsForce) {
  Scene scene = parse_scene(two_balls(GetParam()), "two-balls.json", ".");
  Simulation sim = make_simulation(scene);
  Real largest = 0;
  for (int n = 0; n < 300; ++n) {
    sim.step(scene.timestep);
    const Vec3 raw = sim.instrument_metrics()[0].raw_force;
    const Vec3 sum = sim.tissue_force(0, 0) + sim.tissue_force(1, 0);
    ASSERT_LE((sum - raw).norm(), 1e-12 * (1 + raw.norm())) << "step " << n;
    ASSERT_EQ(sim.tissue_force(0, 0), Vec3::Zero()) << "the left ball is never touched; step " << n;
    largest = std::max(largest, sim.tissue_force(1, 0).norm());
  }
  // The largest tissue RMS speed is the right ball's (the left one is still): √(2 E_kin / m).
  Real kinetic = 0, mass = 0;
  const TissueBody& right = *sim.world().tissues[1];
  for (std::size_t v = 0; v < right.state.velocities.size(); ++v) {
    kinetic += 0.5 * right.settings.masses[v] * right.state.velocities[v].squaredNorm();
    mass += right.settings.masses[v];
  }
  EXPECT_NEAR(sim.metrics().tissue_rms_speed, std::sqrt(2 * kinetic / mass), 1e-9 * (1 + std::sqrt(2 * kinetic / mass)));
  EXPECT_GT(sim.metrics().tissue_rms_speed, 0);
  // The probe's tip 5 mm into the right ball: a push of the order of the response's K·depth.
  EXPECT_GT(largest, 0.1);
  EXPECT_GT(sim.tissue_force(1, 0).z(), 0) << "the ball pushes the probe up";
}

INSTANTIATE_TEST_SUITE_P(Integrators, TissueForce, ::testing::Values("implicit-euler", "xpbd"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param) == "xpbd" ? "Xpbd" : "ImplicitEuler";
                         });

}  // namespace
}  // namespace trocar
