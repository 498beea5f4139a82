// The tacker's outcomes on the hand-built world of task_scene.h: mesh 1 mm above a flat wall.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "procedure/task_scene.h"
#include "trocar/procedure/procedure.h"
#include "trocar/procedure/tacker.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

constexpr std::size_t kWall = 0, kMesh = 1;
constexpr Real kPi = 3.14159265358979323846;

/// Puts the capsule's tip (2.5 mm below its origin) at `tip`.
void put_tip(Simulation& sim, const Vec3& tip) {
  Pose pose;
  pose.translation = tip + Vec3(0, 0, 0.0025);
  sim.place_instrument(0, pose, 0);
}

TackerRules rules() {
  TackerRules r;
  r.mesh_tissue = kMesh;
  return r;
}

TEST(Tacker, DefaultTipIsTheShaftEndAwayFromTheTopVertex) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  put_tip(sim, Vec3(0.01, 0.02, 0.03));
  const TackerTip tip = tacker_tip(sim.world().instruments[0].instrument, rules());
  EXPECT_NEAR((tip.point - Vec3(0.01, 0.02, 0.03)).norm(), 0, 1e-12);
  EXPECT_NEAR((tip.axis - Vec3(0, 0, -1)).norm(), 0, 1e-12);
}

TEST(Tacker, MeshAndTissueUnderTheTipAreFixedTogetherThere) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  const Vec3 tip(0.0061, 0.0037, 0.0015);  // 0.5 mm above the mesh, 1.5 mm above the wall
  put_tip(sim, tip);
  TackerRules r = rules();
  r.pullout_force = 25;
  const TackRecord rec = fire_tacker(sim, 0, r, {});
  EXPECT_EQ(rec.outcome, TackOutcome::kFixed);
  EXPECT_EQ(rec.tissue, kWall);
  ASSERT_EQ(rec.attachment, 0u);
  ASSERT_EQ(sim.attachments().size(), 1u);
  const AttachmentState& a = sim.attachments()[0];
  EXPECT_EQ(a.spec.pullout_force, 25);
  EXPECT_EQ(a.spec.a.tissue, kMesh);
  EXPECT_EQ(a.spec.b.tissue, kWall);
  const World& w = sim.world();
  const Vec3 on_mesh = surface_position(w.tissues[kMesh]->settings, w.tissues[kMesh]->state, a.spec.a);
  const Vec3 on_wall = surface_position(w.tissues[kWall]->settings, w.tissues[kWall]->state, a.spec.b);
  EXPECT_NEAR((on_mesh - Vec3(tip.x(), tip.y(), 0.001)).norm(), 0, 1e-9);
  EXPECT_NEAR((on_wall - Vec3(tip.x(), tip.y(), 0)).norm(), 0, 1e-9);
  EXPECT_TRUE(rec.zone.empty());
  EXPECT_EQ(rec.time, 0);
}

TEST(Tacker, DefaultPullOutIsTheTitaniumSpiralTack) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  put_tip(sim, Vec3(0, 0, 0.0015));
  fire_tacker(sim, 0, rules(), {});
  ASSERT_EQ(sim.attachments().size(), 1u);
  EXPECT_EQ(sim.attachments()[0].spec.pullout_force, 28.6);  // Byrd et al. 2011
}

TEST(Tacker, TissueOnlyMeshOnlyAndNothingAttachNothing) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  struct Case {
    Vec3 tip;
    TackOutcome outcome;
    std::size_t tissue;
  };
  const std::vector<Case> cases = {
      {Vec3(0.052, 0.0, 0.001), TackOutcome::kTissueOnly, kWall},   // 7 mm beyond the mesh's edge
      {Vec3(0.01, 0.01, 0.0025), TackOutcome::kMeshOnly, kNoIndex},    // mesh 1.5 mm, wall 2.5 mm away
      {Vec3(-0.03, -0.03, 0.01), TackOutcome::kNothing, kNoIndex},     // 9 mm above the mesh
      {Vec3(0.2, 0.2, 0.0), TackOutcome::kNothing, kNoIndex},          // beside everything
  };
  for (const Case& c : cases) {
    put_tip(sim, c.tip);
    const TackRecord rec = fire_tacker(sim, 0, rules(), {});
    EXPECT_EQ(rec.outcome, c.outcome) << to_string(rec.outcome);
    EXPECT_EQ(rec.tissue, c.tissue);
    EXPECT_EQ(rec.attachment, kNoIndex);
    EXPECT_NEAR((rec.tip - c.tip).norm(), 0, 1e-12);
  }
  EXPECT_TRUE(sim.attachments().empty());
}

TEST(Tacker, ReachIsTheRulesDistance) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  put_tip(sim, Vec3(0.01, 0.01, 0.0025));  // wall 2.5 mm away: out of the default 2 mm reach
  TackerRules r = rules();
  r.reach = 0.003;
  EXPECT_EQ(fire_tacker(sim, 0, r, {}).outcome, TackOutcome::kFixed);
}

// A shaft 60° off the wall's normal: its face's centre 2.8 mm over the wall (out of reach) but
// the face's low rim, 1.5 mm across, 1.3 mm lower: the reach counts from the face, so mesh and
// wall are both within it. From the centre alone, only the mesh (1.8 mm) would be.
TEST(Tacker, ReachCountsFromTheTipsFaceNotItsCentre) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  put_tip(sim, Vec3(0.03, 0.02, 0.0028));  // 2 cm from the sac
  TackerRules r = rules();
  r.tip_local = Vec3(0, 0, -0.0025);
  r.axis_local = Vec3(std::sin(kPi / 3), 0, -std::cos(kPi / 3));
  ASSERT_EQ(r.tip_radius, 0.0015);  // a 5 mm tacker less its 1 mm bevel
  const TackRecord rec = fire_tacker(sim, 0, r, {});
  EXPECT_EQ(rec.outcome, TackOutcome::kFixed) << to_string(rec.outcome);
  EXPECT_EQ(rec.tissue, kWall);
  // The wall point is under the rim: 1.5 mm × cos 60° = 0.75 mm from under the centre, toward −x.
  const World& w = sim.world();
  const Vec3 on_wall = surface_position(w.tissues[kWall]->settings, w.tissues[kWall]->state, rec.tissue_point);
  EXPECT_NEAR(on_wall.x(), 0.03 - 0.00075, 1e-5);
  TackerRules point = r;
  point.tip_radius = 0;
  EXPECT_EQ(fire_tacker(sim, 0, point, {}).outcome, TackOutcome::kMeshOnly);
}

TEST(Tacker, ZoneAndNearestLandmarkAreRecorded) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  NamedZone zone{"triangle_of_doom", {Vec3(-0.015, -0.015, 0), Vec3(-0.005, -0.015, 0), Vec3(-0.01, -0.005, 0)}, 0.005};
  const std::vector<NamedZone> zones = {zone};
  const std::vector<NamedPoint> marks = {{"a", Vec3(0.03, 0, 0)}, {"b", Vec3(-0.01, -0.02, 0)}};
  put_tip(sim, Vec3(-0.01, -0.01, 0.0015));
  const TackRecord in = fire_tacker(sim, 0, rules(), zones, marks);
  EXPECT_EQ(in.outcome, TackOutcome::kFixed);  // the zone does not stop the tack
  EXPECT_EQ(in.zone, "triangle_of_doom");
  EXPECT_EQ(in.landmark, "b");
  EXPECT_NEAR(in.landmark_distance, std::sqrt(0.01 * 0.01 + 0.0015 * 0.0015), 1e-12);
  put_tip(sim, Vec3(0.01, 0.01, 0.0015));
  EXPECT_TRUE(fire_tacker(sim, 0, rules(), zones, marks).zone.empty());
}

TEST(Tacker, ProcedureLogsATackInAZoneAsAnError) {
  Scene scene = test::task_scene(R"("zones": [{"name": "triangle_of_doom", "depth": 0.004,
      "polygon": [[-0.015, -0.015, 0], [-0.005, -0.015, 0], [-0.01, -0.005, 0]]}],
    "task": {"sac": "sac", "mesh": "mesh"})");
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  put_tip(sim, Vec3(0.01, 0.01, 0.0015));
  EXPECT_EQ(p.fire_tacker(sim, 0).outcome, TackOutcome::kFixed);
  EXPECT_EQ(p.error_count(), 0u);
  put_tip(sim, Vec3(-0.01, -0.01, 0.0015));
  const TackRecord& r = p.fire_tacker(sim, 0);
  EXPECT_EQ(r.zone, "triangle_of_doom");
  ASSERT_EQ(p.tacks().size(), 2u);
  EXPECT_EQ(p.error_count(), 1u);
  const TaskEvent& e = p.events().back();
  EXPECT_EQ(e.kind, TaskEventKind::kTackInZone);
  EXPECT_TRUE(e.error);
  EXPECT_EQ(e.zone, "triangle_of_doom");
  EXPECT_NEAR((e.place - Vec3(-0.01, -0.01, 0.0015)).norm(), 0, 1e-12);
  EXPECT_EQ(sim.attachments().size(), 2u);
}

}  // namespace
}  // namespace trocar
