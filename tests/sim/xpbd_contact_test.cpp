// The xpbd integrator inside Simulation::step: max_force clamps only the reported force, the
// contact inside the solver keeps a thin hook and a blunt probe out of a generated organ on a
// light-soft and a heavy-stiff material, the jaws lift the tissue, and a run repeats bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_targets.h"
#include "probe_scene.h"
#include "trocar/core/error.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/robustness.h"

namespace trocar {
namespace {

Simulation xpbd_probe_sim(Real max_force) {
  std::string text = test::probe_scene_text(0.04, 0.028, 0.1);
  const std::string from = R"("integrator": "implicit-euler")";
  text.replace(text.find(from), from.size(), R"("integrator": "xpbd", "substeps": 4)");
  Scene scene = parse_scene(text, "probe.json", ".");
  scene.settings.response.max_force = max_force;
  return Simulation(std::move(scene.world), scene.settings);
}

// max_force limits the force reported to the instrument and the device, never the tissue's
// correction: 1 mN against 1 kN gives the same tissue bit for bit.
TEST(XpbdContact, MaxForceNeverClampsTheTissuesCorrection) {
  Simulation weak = xpbd_probe_sim(1e-3);
  Simulation strong = xpbd_probe_sim(1e3);
  ASSERT_EQ(weak.world().tissues[0]->integrator.kind(), IntegratorKind::kXpbd);
  Real weak_max = 0, strong_max = 0;
  for (int s = 0; s < 150; ++s) {
    weak.step(1e-3);
    strong.step(1e-3);
    weak_max = std::max(weak_max, weak.instrument_metrics()[0].force.norm());
    strong_max = std::max(strong_max, strong.instrument_metrics()[0].force.norm());
  }
  EXPECT_EQ(weak.state_hash(), strong.state_hash());
  EXPECT_LE(weak_max, 1e-3 * (1 + 1e-12));
  EXPECT_GT(strong_max, 0.05);
  EXPECT_EQ(weak.instrument_metrics()[0].raw_force, strong.instrument_metrics()[0].raw_force);
  EXPECT_EQ(weak.metrics().substeps, 4u);
}

TEST(XpbdContact, SubstepsKeyNeedsTheXpbdIntegrator) {
  std::string text = test::probe_scene_text(0.04, 0.028, 0.1);
  const std::string from = R"("integrator": "implicit-euler")";
  text.replace(text.find(from), from.size(), R"("integrator": "implicit-euler", "substeps": 4)");
  EXPECT_THROW(parse_scene(text, "probe.json", "."), Error);
  text = test::probe_scene_text(0.04, 0.028, 0.1);
  text.replace(text.find(from), from.size(), R"("integrator": "xpbd", "substeps": 0)");
  EXPECT_THROW(parse_scene(text, "probe.json", "."), Error);
}

// The suite's smallest generated organ (2,000 T) on the lightest and the heaviest contact
// material, under the 1.2 mm hook and the 10 mm probe: press, slide and a 1 m/s poke meet the
// contact targets (p99 ≤ 0.5 mm, max ≤ 1 mm, no tunneling) with a force on the tool.
TEST(XpbdContact, HookAndProbeStayOutOfAGeneratedOrgan) {
  const std::vector<SuiteOrgan> family = generated_organs(1);
  ASSERT_FALSE(family.empty());
  const SuiteOrgan& organ = family.front();
  const SuiteSolver solver = *parse_suite_solver("xpbd");
  for (const char* material : {"light-soft", "heavy-stiff"})
    for (const char* tool : {"hook", "probe10"}) {
      const SuiteInstrument instrument = *suite_instrument(tool);
      for (const SuiteMotion motion : {SuiteMotion::kPress, SuiteMotion::kSlide, SuiteMotion::kPoke}) {
        const SuiteRun r = run_suite_case(organ, motion, suite_material(material, organ), instrument, solver);
        SCOPED_TRACE(std::string(material) + " " + tool + " " + r.motion);
        test::expect_contact_targets(r);
        EXPECT_GT(r.contact_steps, 50u);
        EXPECT_GT(r.raw_force_max, 0.005);
      }
    }
}

// Closed jaws hold the tissue they touch and lift it: the grasp-lift run ends with tissue
// vertices more than 6 mm above where they started, and the grasper feels the tissue's weight.
TEST(XpbdContact, GrasperLiftsTheTissue) {
  const std::vector<SuiteOrgan> family = generated_organs(1);
  const SuiteOrgan& organ = family.front();
  const SuiteInstrument grasper = *suite_instrument("grasper");
  Real duration = 0;
  World world = suite_world(organ, SuiteMotion::kGraspLift, suite_material("medium", organ).material, grasper,
                            IntegratorKind::kXpbd, duration);
  const Real top_before = Aabb::of_points(world.tissues[0]->state.positions).max.z();
  Simulation sim(std::move(world), suite_settings(ResponseMethod::kSdf));
  const auto steps = static_cast<int>(std::ceil(duration / 1e-3));
  Real lift_force = 0;
  for (int s = 0; s < steps; ++s) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite);
    lift_force = std::max(lift_force, -sim.instrument_metrics()[0].raw_force.z());
  }
  const Real top_after = Aabb::of_points(sim.world().tissues[0]->state.positions).max.z();
  EXPECT_GT(top_after - top_before, 0.006);
  EXPECT_GT(lift_force, 0.01);
}

// The same world twice: the same state hash after every step (one thread, fixed orders).
TEST(XpbdContact, RunsRepeatBitForBit) {
  Simulation a = xpbd_probe_sim(10), b = xpbd_probe_sim(10);
  for (int s = 0; s < 120; ++s) {
    a.step(1e-3);
    b.step(1e-3);
    ASSERT_EQ(a.state_hash(), b.state_hash()) << "step " << s;
  }
}

}  // namespace
}  // namespace trocar
