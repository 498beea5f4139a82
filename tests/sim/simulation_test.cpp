// Simulation::step on a probe pressing into a sphere: contacts, force direction, determinism,
// settling at rest, collision period.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "probe_scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {


TEST(KeyframeMotion, InterpolatesPositionJawAndSlerpsRotation) {
  Keyframe a;
  a.t = 0;
  a.position = Vec3(0, 0, 0);
  Keyframe b;
  b.t = 2;
  b.position = Vec3(2, 0, 0);
  b.jaw = 1;
  b.rotation = Quat(Eigen::AngleAxis<Real>(M_PI / 2, Vec3::UnitZ()));
  const KeyframeMotion motion({b, a});  // unsorted on purpose
  const MotionSample mid = motion.sample(0.5);
  EXPECT_NEAR(mid.pose.translation.x(), 0.5, 1e-15);
  EXPECT_NEAR(mid.jaw, 0.25, 1e-15);
  EXPECT_NEAR(Eigen::AngleAxis<Real>(mid.pose.rotation).angle(), M_PI / 8, 1e-12);
  EXPECT_EQ(motion.sample(-1).pose.translation, Vec3::Zero());
  EXPECT_EQ(motion.sample(5).pose.translation, Vec3(2, 0, 0));
}

TEST(Simulation, ProbePressingIntoSphereMakesContactsAndAnOpposingForce) {
  Scene scene = test::probe_scene(0.04, 0.022, 0.1);  // tip 8 mm below the top at the end
  Simulation sim(std::move(scene.world), scene.settings);
  std::uint32_t max_contacts = 0;
  Real max_depth = 0;
  for (int n = 0; n < 150; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite) << "step " << n;
    max_contacts = std::max(max_contacts, m.contacts);
    max_depth = std::max(max_depth, m.penetration_max);
  }
  EXPECT_GT(max_contacts, 5u);
  const Vec3 f = sim.instrument_metrics()[0].force;
  // The probe moved along −z: the tissue pushes back along +z, more than sideways (the OBB depth
  // of a round tip on an icosphere's facets is not symmetric: ~40 % sideways measured).
  EXPECT_GT(f.z(), 0.05) << f.transpose();
  EXPECT_LT(std::hypot(f.x(), f.y()), 0.5 * f.z()) << f.transpose();
  // The response keeps the probe from sinking the full 8 mm into the tissue.
  EXPECT_LT(max_depth, 8e-3);
  // The surface under the probe was pushed down.
  const auto& x = sim.world().tissues[0]->state.positions;
  Real top = -1;
  for (const Vec3& p : x)
    if (std::hypot(p.x(), p.y()) < 2e-3) top = std::max(top, p.z());
  EXPECT_LT(top, 0.0295);
}

// The step's penetration metrics skip vertices outside the tissue's box, batch the rest and
// refit MeshDistance lazily; they must equal the plain definition: every instrument vertex's
// signed distance by brute force over all triangles of the deformed surface.
TEST(Simulation, PenetrationMetricsEqualBruteForceOverEveryVertex) {
  Scene scene = test::probe_scene(0.04, 0.018, 0.1);  // tip 12 mm below the top at the end
  Simulation sim(std::move(scene.world), scene.settings);
  const TissueBody& ball = *sim.world().tissues[0];
  MeshDistance reference(ball.state.positions, ball.settings.triangles);
  int steps_inside = 0;
  for (int n = 0; n < 150; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    reference.refit(ball.state.positions);
    std::uint32_t inside = 0;
    Real deepest = 0;
    for (const Vec3& p : sim.world().instruments[0].instrument.world_positions()) {
      const Real d = reference.signed_distance_brute_force(p).distance;
      if (d < 0) {
        ++inside;
        deepest = std::max(deepest, -d);
      }
    }
    ASSERT_EQ(m.vertices_inside, inside) << "step " << n;
    ASSERT_EQ(m.penetration_max, deepest) << "step " << n;
    steps_inside += inside > 0 ? 1 : 0;
  }
  EXPECT_GT(steps_inside, 50);
}

// A non-finite coordinate anywhere in a tissue's state makes the step report finite = false.
TEST(Simulation, NonFiniteStateIsReported) {
  for (const Real bad : {std::numeric_limits<Real>::quiet_NaN(), std::numeric_limits<Real>::infinity(),
                         -std::numeric_limits<Real>::infinity()}) {
    Scene scene = test::probe_scene(0.04, 0.03, 0.1);
    Simulation sim(std::move(scene.world), scene.settings);
    for (int n = 0; n < 5; ++n) ASSERT_TRUE(sim.step(1e-3).finite);
    MassSpringState& state = sim.world().tissues[0]->state;
    const auto top = std::max_element(state.positions.begin(), state.positions.end(),
                                      [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });
    state.velocities[static_cast<std::size_t>(top - state.positions.begin())].y() = bad;  // a free vertex
    EXPECT_FALSE(sim.step(1e-3).finite) << bad;
  }
}

std::uint64_t hash_after(const std::string& text, int steps) {
  Scene scene = parse_scene(text, "probe.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  for (int n = 0; n < steps; ++n) sim.step(1e-3);
  return sim.state_hash();
}

TEST(Simulation, DeterministicStateHash) {
  const std::string text = test::probe_scene_text(0.04, 0.022, 0.1);
  const std::uint64_t a = hash_after(text, 120);
  const std::uint64_t b = hash_after(text, 120);
  EXPECT_EQ(a, b);
  const std::uint64_t c = hash_after(test::probe_scene_text(0.04, 0.023, 0.1), 120);
  EXPECT_NE(a, c);
  EXPECT_EQ(hash_hex(a).size(), 16u);
}

/// Presses the probe 2 mm into the ball, holds it, and returns the instrument force (z) and the
/// fastest tissue vertex over the last 200 ms of 1.5 s.
struct HoldResult {
  std::vector<Real> force;
  Real speed = 0;
};
HoldResult hold_probe(ResponseMethod method, bool depth_cap,
                      Real correction_speed = ResponseSettings{}.correction_speed) {
  Scene scene = test::probe_scene(0.035, 0.028, 0.05);
  scene.settings.response.method = method;
  scene.settings.response.depth_cap = depth_cap;
  scene.settings.response.correction_speed = correction_speed;
  Simulation sim(std::move(scene.world), scene.settings);
  HoldResult out;
  for (int n = 0; n < 1500; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    EXPECT_TRUE(m.finite);
    if (!m.finite) break;
    if (n >= 1300) {
      out.force.push_back(sim.instrument_metrics()[0].force.z());
      out.speed = std::max(out.speed, m.max_speed);
    }
  }
  return out;
}

Real relative_deviation(const std::vector<Real>& v) {
  Real mean = 0, square = 0;
  for (Real f : v) mean += f;
  mean /= static_cast<Real>(v.size());
  for (Real f : v) square += (f - mean) * (f - mean);
  return std::sqrt(square / static_cast<Real>(v.size())) / mean;
}

TEST(Simulation, RestingProbeSettlesWithoutJitter) {
  // Every penalty method with the simulator's defaults: the seed's `obb` with its depth cap,
  // `normal`, and `project` / `primitive`, whose position correction is gated by the probe's
  // approach. (`sdf`: SdfRestingProbeSettles below.)
  for (const ResponseMethod method :
       {ResponseMethod::kObb, ResponseMethod::kNormal, ResponseMethod::kProject, ResponseMethod::kPrimitive}) {
    SCOPED_TRACE(response_method_name(method));
    const HoldResult r = hold_probe(method, true);
    ASSERT_EQ(r.force.size(), 200u);
    // Velocity → 0: every tissue vertex slower than 1 cm/s over the last 200 ms (it was ~0.3 m/s
    // while pressing).
    EXPECT_LT(r.speed, 1e-2);
    // Steady contact force, no on/off chatter: never zero, relative standard deviation ≤ 15 %
    // (contacts still appear and vanish at the rim of the contact patch).
    EXPECT_GT(*std::min_element(r.force.begin(), r.force.end()), 0.0);
    EXPECT_LT(relative_deviation(r.force), 0.15);
  }
}

TEST(Simulation, SdfRestingProbeSettles) {
  // The constraint holds the probe with a steady force (deviation ≤ 15 %, never zero) and the
  // tissue comes to rest but for brief stick–slip peaks of the position friction under the
  // capsule's tip (measured 1.5 cm/s at most over the last 200 ms; 0.1 mm/s between them): 2 cm/s
  // here against the penalty methods' 1 cm/s (docs/response.md).
  const HoldResult r = hold_probe(ResponseMethod::kSdf, true);
  ASSERT_EQ(r.force.size(), 200u);
  EXPECT_LT(r.speed, 2e-2);
  EXPECT_GT(*std::min_element(r.force.begin(), r.force.end()), 0.0);
  EXPECT_LT(relative_deviation(r.force), 0.15);
}

TEST(Simulation, UncappedSeedChattersOnARestingProbe) {
  // The seed's step 7 verbatim: PD reaches to the side of the capsule's box however shallow the
  // contact, so the force jumps between 0 and K·(box distance) and the tissue never settles.
  const HoldResult r = hold_probe(ResponseMethod::kObb, false);
  ASSERT_EQ(r.force.size(), 200u);
  const Real min_force = *std::min_element(r.force.begin(), r.force.end());
  std::printf("[ uncapped obb ] late speed %.4f m/s, min force %.4f N, relative deviation %.3f\n", r.speed,
              min_force, relative_deviation(r.force));
  // Measured: 0.74 m/s, contact lost (force 0) within the window, deviation 164 %.
  EXPECT_GT(r.speed, 0.1);
  EXPECT_EQ(min_force, 0.0);
  EXPECT_GT(relative_deviation(r.force), 0.5);
}

TEST(Simulation, UngatedCorrectionChattersOnARestingProbe) {
  // project and primitive with the full position correction at every contact: each step pushes
  // the surface off the held probe, it springs back, and the contact opens and closes.
  for (const ResponseMethod method : {ResponseMethod::kProject, ResponseMethod::kPrimitive}) {
    SCOPED_TRACE(response_method_name(method));
    const HoldResult r = hold_probe(method, true, 0.0);
    ASSERT_EQ(r.force.size(), 200u);
    const Real min_force = *std::min_element(r.force.begin(), r.force.end());
    std::printf("[ ungated %s ] late speed %.4f m/s, min force %.4f N, relative deviation %.3f\n",
                response_method_name(method), r.speed, min_force, relative_deviation(r.force));
    // Measured: 0.61 m/s, force 0 within the window, deviation 100 % (gated: < 1 mm/s, 0.2–0.4 %).
    EXPECT_GT(r.speed, 0.1);
    EXPECT_EQ(min_force, 0.0);
    EXPECT_GT(relative_deviation(r.force), 0.5);
  }
}

TEST(Simulation, CollisionPeriodDetectsEveryKthStep) {
  Scene scene = test::probe_scene(0.04, 0.022, 0.1);
  scene.settings.collision_period = 0.005;
  Simulation sim(std::move(scene.world), scene.settings);
  int detections = 0;
  for (int n = 0; n < 100; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    detections += m.detected ? 1 : 0;
    if (!m.detected) {
      EXPECT_EQ(m.contacts, 0u);
    }
  }
  EXPECT_EQ(detections, 20);
}

TEST(Simulation, FastProbeThroughSlowDetectorCountsTunneling) {
  // 1 m/s with detection every 20 ms: the tip goes 20 mm between detections.
  Scene scene = test::probe_scene(0.04, -0.01, 0.05);
  scene.settings.collision_period = 0.02;
  Simulation sim(std::move(scene.world), scene.settings);
  std::uint32_t tunneling = 0;
  for (int n = 0; n < 60; ++n) tunneling += sim.step(1e-3).tunneling_events;
  EXPECT_GT(tunneling, 0u);
}

TEST(Simulation, SlowPressAnsweredByContactsCountsNoTunneling) {
  // The shipped press scene's hook probe pressing slowly (10 mm/s) into the liver lobe with
  // detection every step: the response answers every touch, but after it the deforming surface
  // springs back over hook vertices by tens of µm. Those are the tissue moving onto the tool
  // (seen by the next detection), not the instrument crossing unseen: no tunneling.
  const std::string text = R"({
  "schema": 1, "name": "slow-press", "timestep": 0.001, "duration": 1.0, "gravity": [0, 0, -9.81],
  "tissues": [{ "name": "liver",
    "mesh": { "generate": "liver-lobe", "length": 0.16, "width": 0.10, "thickness": 0.06, "subdivisions": 3 },
    "material": { "preset": "liver" },
    "fixed": { "below_plane": { "point": [0, 0, -0.008], "normal": [0, 0, 1] } },
    "integrator": "implicit-euler" }],
  "instruments": [{ "name": "probe", "mesh": { "generate": "hook-probe", "shaft_length": 0.15 }, "top_vertex": "auto",
    "motion": { "keyframes": [
      { "t": 0.0, "position": [0, 0, 0.031] }, { "t": 0.05, "position": [0, 0, 0.031] },
      { "t": 0.9, "position": [0, 0, 0.0225] } ] } }],
  "collision": { "broad_phase": "ohc", "cell_size": "auto", "period": 0.001 },
  "response": { "method": "obb", "stiffness": 2000, "damping": 5, "max_force": 10 }
})";
  Scene scene = parse_scene(text, "slow_press.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  std::uint32_t tunneling = 0, contact_steps = 0, inside_steps = 0;
  for (int n = 0; n < 950; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite) << "step " << n;
    tunneling += m.tunneling_events;
    contact_steps += m.contacts > 0 ? 1 : 0;
    inside_steps += m.vertices_inside > 0 ? 1 : 0;
  }
  EXPECT_GT(contact_steps, 100u);  // the probe does press on the tissue
  EXPECT_GT(inside_steps, 10u);    // and hook vertices do end steps inside the surface
  EXPECT_EQ(tunneling, 0u);
}

}  // namespace
}  // namespace trocar
