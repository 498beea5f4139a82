// The sdf response inside Simulation::step: max_force clamps only the reported force, and the
// constraint keeps a pressed, sliding and poking probe out of a generated organ.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_targets.h"
#include "probe_scene.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/robustness.h"

namespace trocar {
namespace {

/// The probe scene (capsule pressing 5 mm into a sphere) with `method` and `max_force`.
Simulation probe_sim(ResponseMethod method, Real max_force) {
  Scene scene = parse_scene(test::probe_scene_text(0.04, 0.028, 0.1), "probe.json", ".");
  scene.settings.response.method = method;
  scene.settings.response.max_force = max_force;
  return Simulation(std::move(scene.world), scene.settings);
}

// max_force limits the force reported to the instrument and the device, never the
// correction of the tissue. A limit of 1 mN against one of 1 kN: the same tissue, bit for bit,
// for every method; only the reported force differs (and is capped at 1 mN).
TEST(MaxForce, NeverClampsTheTissuesCorrection) {
  for (const ResponseMethod method : {ResponseMethod::kSdf, ResponseMethod::kObb, ResponseMethod::kProject,
                                      ResponseMethod::kPrimitive, ResponseMethod::kNormal}) {
    SCOPED_TRACE(response_method_name(method));
    Simulation weak = probe_sim(method, 1e-3);
    Simulation strong = probe_sim(method, 1e3);
    Real weak_max = 0, strong_max = 0;
    for (int s = 0; s < 150; ++s) {
      weak.step(1e-3);
      strong.step(1e-3);
      weak_max = std::max(weak_max, weak.instrument_metrics()[0].force.norm());
      strong_max = std::max(strong_max, strong.instrument_metrics()[0].force.norm());
    }
    EXPECT_EQ(weak.state_hash(), strong.state_hash());
    EXPECT_LE(weak_max, 1e-3 * (1 + 1e-12));
    EXPECT_GT(strong_max, 0.05);  // the press needs tenths of a newton
    EXPECT_EQ(weak.instrument_metrics()[0].raw_force, strong.instrument_metrics()[0].raw_force);
  }
}

// sdf is the default: of the methods, the most suite runs within the targets (docs/robustness.md).
TEST(SdfContact, IsTheDefaultMethod) {
  EXPECT_EQ(ResponseSettings{}.method, ResponseMethod::kSdf);
  const Scene scene = parse_scene(R"({"schema": 1, "name": "x", "timestep": 0.001, "duration": 0.01})", "x.json", ".");
  EXPECT_EQ(scene.settings.response.method, ResponseMethod::kSdf);
  EXPECT_EQ(parse_response_method("sdf"), ResponseMethod::kSdf);
  EXPECT_STREQ(response_method_name(ResponseMethod::kSdf), "sdf");
}

// The suite's smallest generated organ (2,000 T, 2.5 mm edges) under the hook probe (a 1.2 mm
// wire): press, slide and a 1 m/s poke meet the contact targets with sdf (p99 ≤ 0.5 mm, max ≤
// 1 mm, no tunneling; measured 0.00, 0.00 and 0.02 mm) and stay stable with a force on the tool.
TEST(SdfContact, PressSlideAndPokeOnAGeneratedOrgan) {
  const std::vector<SuiteOrgan> family = generated_organs(1);
  ASSERT_FALSE(family.empty());
  const SuiteOrgan& organ = family.front();
  for (const SuiteMotion motion : {SuiteMotion::kPress, SuiteMotion::kSlide, SuiteMotion::kPoke}) {
    const SuiteRun r = run_suite_case(organ, motion, ResponseMethod::kSdf);
    SCOPED_TRACE(r.motion);
    test::expect_contact_targets(r);
    EXPECT_GT(r.contact_steps, 100u);
    EXPECT_GT(r.raw_force_max, 0.01);
  }
}

// A 1.2 mm wire pressed 8 mm into a finer organ (lobe-18K, 1.6 mm edges) ends partly inside:
// measured p99 4.0 mm. The bound catches a regression; the target is open (docs/robustness.md).
TEST(SdfContact, DeepPressOnAFineOrganIsAnOpenTarget) {
  const std::vector<SuiteOrgan> family = generated_organs(1);
  ASSERT_GE(family.size(), 5u);
  const SuiteRun r = run_suite_case(family[4], SuiteMotion::kPress, ResponseMethod::kSdf);
  EXPECT_TRUE(r.stable);
  EXPECT_LE(r.penetration_p99, 5e-3);
  EXPECT_LE(r.tunneling, 10u);
}

}  // namespace
}  // namespace trocar
