// study/scene_driver.h: the step count of a duration, the tissue mass, and drive() stepping a
// stable world to the end and stopping at the first unstable step.
#include <gtest/gtest.h>

#include <cmath>

#include "trocar/core/stability.h"
#include "trocar/study/robustness.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

TEST(SceneDriver, StepCountRoundsUpButIgnoresRoundingErrors) {
  EXPECT_EQ(step_count(2.0, 0.001), 2000u);
  EXPECT_EQ(step_count(0.0105, 0.001), 11u);  // a partial step is a step
  EXPECT_EQ(step_count((0.1 + 0.2), 0.1), 3u);  // 3.0000000000000004 steps: not 4
  EXPECT_EQ(step_count(0.0, 0.001), 0u);
}

/// The generated lobe, "medium" (0.3 kg), held at rest under the hook: no contact.
World rest_world(Real& duration) {
  const SuiteOrgan organ = generated_organs(1).front();
  const SuiteMaterial material = suite_material("medium", organ);
  const SuiteInstrument hook = *suite_instrument("hook");
  return suite_world(organ, SuiteMotion::kRest, material.material, hook, IntegratorKind::kImplicitEuler, duration);
}

TEST(SceneDriver, TissueMassIsTheMaterialsMass) {
  Real duration = 0;
  const World world = rest_world(duration);
  EXPECT_NEAR(tissue_mass(world), 0.3, 1e-9);
}

TEST(SceneDriver, CallsBackOnceAStepToTheEndOfAStableRun) {
  Real duration = 0;
  Simulation sim(rest_world(duration), suite_settings(ResponseMethod::kSdf));
  std::size_t calls = 0;
  double last_time = 0;
  const DriveResult r = drive(sim, 0.001, 50, [&](const StepMetrics& m) {
    ++calls;
    last_time = m.time;
  });
  EXPECT_TRUE(r.stable);
  EXPECT_EQ(r.steps, 50u);
  EXPECT_EQ(calls, 50u);
  EXPECT_NEAR(last_time, 0.05, 1e-12);
  EXPECT_NEAR(sim.time(), 0.05, 1e-12);
}

TEST(SceneDriver, StopsAfterTheFirstUnstableStep) {
  Real duration = 0;
  World world = rest_world(duration);
  // Every free vertex at 50 m/s: the energy is far above ½·M·(10 m/s)² from the first step on
  // (the fixed bottom fifth carries no speed; the rest is still ≥ 70 % of the mass).
  TissueBody& tissue = *world.tissues.front();
  for (std::size_t i = 0; i < tissue.state.velocities.size(); ++i)
    if (tissue.settings.inverse_masses[i] > 0) tissue.state.velocities[i] = Vec3(50, 0, 0);
  const Real mass = tissue_mass(world);
  Simulation sim(std::move(world), suite_settings(ResponseMethod::kSdf));
  std::size_t calls = 0;
  double energy = 0;
  const DriveResult r = drive(sim, 0.001, 100, [&](const StepMetrics& m) {
    ++calls;
    energy = m.kinetic_energy;
  });
  EXPECT_FALSE(r.stable);
  EXPECT_EQ(r.steps, 1u);
  EXPECT_EQ(calls, 1u);  // the unstable step is handed over, then the loop stops
  EXPECT_GT(energy, stable_energy_bound(mass));
}

}  // namespace
}  // namespace trocar
