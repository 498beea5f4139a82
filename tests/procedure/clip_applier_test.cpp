// A clip applier (docs/electrosurgery.md, "Bleeding"): its "fire" clips the bleeding point between
// its jaws and nothing farther; a grasper's fire clips nothing.
#include <gtest/gtest.h>

#include "trocar/mesh/inguinal_anatomy.h"
#include "trocar/mesh/instruments.h"
#include "trocar/procedure/actions.h"
#include "trocar/sim/simulation.h"
#include "support/vessel.h"

namespace trocar {
namespace {

/// A 4 mm vein (a tube of radius 2 mm along x, its ends held), a clip applier and a grasper, both
/// 3 cm above it.
Simulation vein_and_tools() {
  World world;
  test::add_held_vessel(world, "vein", Vec3::Zero(), 0.015, 0.002, 12, 0.014, VesselSpec{0.004, false});
  const InstrumentMesh jaws = make_grasper();
  world.add_instrument("clips", Instrument(jaws.mesh, Vec3::UnitZ()), KeyframeMotion({{0, Vec3(0, 0, 0.03), Quat::Identity(), 0}}))
      .tool = "clip-applier";
  world.add_instrument("grasper", Instrument(jaws.mesh, Vec3::UnitZ()), KeyframeMotion({{0, Vec3(0.01, 0, 0.03), Quat::Identity(), 0}}))
      .tool = "grasper";
  return Simulation(std::move(world), SimulationSettings{});
}

TEST(ClipApplier, FiringClipsTheBleedingPointBetweenItsJawsAndNothingFarther) {
  Simulation sim = vein_and_tools();
  for (int n = 0; n < 10; ++n) sim.step(1e-3);
  // The vein's top opened: it bleeds (4 mm: the hook could not seal it).
  const MassSpringSettings& s = sim.world().tissues[0]->settings;
  std::uint32_t top = 0;
  for (std::uint32_t k = 0; k < s.triangles.size(); ++k) {
    const auto centre = [&](std::uint32_t j) {
      return (s.rest_positions[s.triangles[j][0]] + s.rest_positions[s.triangles[j][1]] + s.rest_positions[s.triangles[j][2]]) / 3;
    };
    if ((centre(k) - Vec3(0, 0, 0.002)).norm() < (centre(top) - Vec3(0, 0, 0.002)).norm()) top = k;
  }
  const std::uint32_t cut[] = {top};
  sim.cut(0, cut);
  for (int n = 0; n < 10; ++n) sim.step(1e-3);
  ASSERT_EQ(sim.bleeding().wounds().size(), 1u);
  // From 3 cm away the clip lands on nothing; the grasper's fire does nothing either.
  apply_actions(sim, 0, kActionFire, nullptr);
  apply_actions(sim, 1, kActionFire, nullptr);
  EXPECT_EQ(sim.bleeding().state(0), WoundState::kBleeding);
  EXPECT_EQ(sim.clip_at(0), -1);
  // Brought to 3 mm over the bleeding point (within its 5 mm jaws): the grasper still clips
  // nothing, the clip applier closes the wound and the bleeding stops.
  const Vec3 wound = sim.world().tissues[0]->state.positions[sim.bleeding().wounds()[0].vertex];
  sim.place_instrument(1, Pose{Quat::Identity(), wound + Vec3(0, 0, 0.003)}, 0);
  apply_actions(sim, 1, kActionFire, nullptr);
  EXPECT_EQ(sim.bleeding().state(0), WoundState::kBleeding);
  sim.place_instrument(0, Pose{Quat::Identity(), wound + Vec3(0, 0, 0.003)}, 0);
  apply_actions(sim, 0, kActionFire, nullptr);
  EXPECT_EQ(sim.bleeding().state(0), WoundState::kClipped);
  const Real bled = sim.bleeding().emitted();
  for (int n = 0; n < 50; ++n) sim.step(1e-3);
  EXPECT_EQ(sim.bleeding().emitted(), bled);
  ASSERT_TRUE(sim.bleeding().time_to_haemostasis(0).has_value());
  EXPECT_NEAR(*sim.bleeding().time_to_haemostasis(0), 0.010, 1e-9);  // opened at 10 ms, clipped at 20 ms
}

}  // namespace
}  // namespace trocar
