// The penetration metrics (box cull, batched queries seeded by last step's nearest triangles, refit
// once per step) must equal the plain definition, every instrument vertex's signed distance by
// brute force over every triangle of the deformed surface: while the probe presses, slides and
// lifts, and when the tissue is moved between steps by hand (the seeds and the second MeshDistance
// then describe an old surface).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "probe_scene.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

/// The probe–sphere scene of probe_scene.h (the probe's tip is 3 mm below its origin) with a path
/// that presses the tip 4 mm into the top of the ball (t = 0.1 s), slides it 12 mm sideways (to
/// 0.25 s) and lifts it off (to 0.35 s).
std::string press_slide_lift_text() {
  return test::probe_scene_text_with_keyframes(R"({"t": 0, "position": [0, 0, 0.036]},
                                                {"t": 0.1, "position": [0, 0, 0.029]},
                                                {"t": 0.25, "position": [0.012, 0, 0.0285]},
                                                {"t": 0.35, "position": [0.012, 0, 0.04]})");
}

/// The metrics' vertices_inside and penetration_max from every instrument vertex's brute-force
/// signed distance to the tissue as it is now.
struct Reference {
  std::uint32_t inside = 0;
  Real deepest = 0;
};
Reference reference_metrics(const Simulation& sim, MeshDistance& reference) {
  const TissueBody& tissue = *sim.world().tissues[0];
  reference.refit(tissue.state.positions);
  Reference r;
  for (const Vec3& p : sim.world().instruments[0].instrument.world_positions()) {
    const Real d = reference.signed_distance_brute_force(p).distance;
    if (d < 0) {
      ++r.inside;
      r.deepest = std::max(r.deepest, -d);
    }
  }
  return r;
}

TEST(PenetrationMetrics, EqualBruteForceWhilePressingSlidingAndLifting) {
  Scene scene = parse_scene(press_slide_lift_text(), "slide.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  const TissueBody& ball = *sim.world().tissues[0];
  MeshDistance reference(ball.state.positions, ball.settings.triangles);
  int steps_inside = 0, steps_moving_inside = 0;
  for (int n = 0; n < 400; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite) << "step " << n;
    const Reference r = reference_metrics(sim, reference);
    ASSERT_EQ(m.vertices_inside, r.inside) << "step " << n;
    ASSERT_EQ(m.penetration_max, r.deepest) << "step " << n;
    steps_inside += r.inside > 0 ? 1 : 0;
    steps_moving_inside += r.inside > 0 && n >= 100 && n < 250 ? 1 : 0;
  }
  EXPECT_GT(steps_inside, 150);
  EXPECT_GT(steps_moving_inside, 100);  // the slide happens in contact
}

// Positions changed by hand between steps (a user's edit, a reset) are measured like any motion:
// the whole ball lifted 2.5 mm under a probe that rests about 1 mm above it puts the probe's tip
// inside, and the metrics must see it although the probe itself did not move. (The tip is off the
// ball's axis, below its top, so it is in the ball's box and has been queried before.)
TEST(PenetrationMetrics, TissueMovedBetweenStepsIsMeasuredAnew) {
  Scene scene = parse_scene(press_slide_lift_text(), "slide.json", ".");
  // Hold the probe's tip at (0.01, 0, 0.0295), 1.2 mm above the ball's surface (z = 0.02828 there),
  // for the whole run.
  InstrumentBody& probe = scene.world.instruments[0];
  Keyframe hold;
  hold.position = Vec3(0.01, 0, 0.0325);
  probe.motion = KeyframeMotion({hold});
  Simulation sim(std::move(scene.world), scene.settings);
  TissueBody& ball = *sim.world().tissues[0];
  MeshDistance reference(ball.state.positions, ball.settings.triangles);
  for (int n = 0; n < 20; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_EQ(m.vertices_inside, 0u) << "step " << n;
  }
  for (Vec3& x : ball.state.positions) x.z() += 2.5e-3;
  const StepMetrics& m = sim.step(1e-3);
  const Reference r = reference_metrics(sim, reference);
  EXPECT_GT(r.inside, 0u);
  EXPECT_EQ(m.vertices_inside, r.inside);
  EXPECT_EQ(m.penetration_max, r.deepest);
}

}  // namespace
}  // namespace trocar
