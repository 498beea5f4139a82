// The task's completion tests and their order, on the hand-built world of task_scene.h.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "procedure/task_scene.h"
#include "trocar/mesh/generate.h"
#include "trocar/procedure/procedure.h"
#include "trocar/procedure/task_measures.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

constexpr std::size_t kMesh = 1, kSac = 2;

void put_tip(Simulation& sim, const Vec3& tip) {
  Pose pose;
  pose.translation = tip + Vec3(0, 0, 0.0025);
  sim.place_instrument(0, pose, 0);
}

void shift(Simulation& sim, std::size_t tissue, const Vec3& by) {
  for (Vec3& x : sim.world().tissues[tissue]->state.positions) x += by;
}

TEST(TaskMeasures, AreaBeyondAPlaneSplitsACubeExactly) {
  // A 2 × 2 × 2 cube centred at the origin, plane z = 0.5: the top face (4) and the four sides'
  // upper 0.5 (4 × 2 × 0.5) lie beyond: 8 of 24.
  const TriMesh cube = make_box(2, 2, 2);
  const AreaSplit split = area_beyond_plane(cube.positions, cube.triangles, {Vec3(0, 0, 0.5), Vec3(0, 0, 1)});
  EXPECT_NEAR(split.total, 24, 1e-12);
  EXPECT_NEAR(split.beyond, 8, 1e-12);
  // A tilted plane through the centre halves it by symmetry.
  const AreaSplit half = area_beyond_plane(cube.positions, cube.triangles, {Vec3::Zero(), Vec3(1, 2, 3).normalized()});
  EXPECT_NEAR(half.fraction(), 0.5, 1e-12);
}

TEST(TaskMeasures, FlippedAreaIsTheFoldedOverStrip) {
  const TriMesh flat = make_sheet(0.09, 0.09, 18, 18);
  EXPECT_EQ(flipped_area(flat.positions, flat.triangles, Vec3(0, 0, 1)), 0);
  EXPECT_EQ(flipped_area(flat.positions, flat.triangles, Vec3(0, 0, -1)), 0);  // either side is the sheet's
  TriMesh folded = flat;
  for (Vec3& x : folded.positions)
    if (x.x() > 0.025 + 1e-9) x.x() = 0.05 - x.x();  // the last 2 cm folded back (flat onto the sheet)
  EXPECT_NEAR(flipped_area(folded.positions, folded.triangles, Vec3(0, 0, 1)), 0.02 * 0.09, 1e-12);
}

TEST(TaskMeasures, CoverageOfADiscByAShiftedSquareIsTheDiscLessItsSegment) {
  // Disc of radius R = 4 cm; a 9 cm square centred 1.025 cm off leaves the segment x < −3.475 cm
  // uncovered: area R² acos((R−h)/R) − (R−h)√(2Rh − h²), h = 5.25 mm. The 0.5 mm grid's nodes
  // fall half a spacing either side of the square's edge, so the sampled share is a midpoint rule.
  const WallPlane wall{Vec3::Zero(), Vec3(0, 0, 1)};
  CoverageRegion region(wall, {}, Vec3::Zero(), 0.04, 0.0005);
  TriMesh sheet = make_sheet(0.09, 0.09, 18, 18);
  EXPECT_EQ(region.covered_fraction(sheet.positions, sheet.triangles), 1);
  for (Vec3& x : sheet.positions) x += Vec3(0.01025, 0, 0.002);
  const double R = 0.04, h = 0.00525;
  const double segment = R * R * std::acos((R - h) / R) - (R - h) * std::sqrt(2 * R * h - h * h);
  const double expected = 1 - segment / (std::numbers::pi * R * R);
  EXPECT_NEAR(region.covered_fraction(sheet.positions, sheet.triangles), expected, 0.001);
}

TEST(Task, SacFractionIsTheAreaBeyondTheWall) {
  Scene scene = test::task_scene(R"("task": {"sac": "sac", "mesh": "mesh", "reduced_fraction": 0.7})");
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  // The 2 cm cube from z = −0.005 to 0.015: its top (4 cm²) and the sides' upper 1.5 cm (4 × 3 cm²)
  // of 24 cm² lie in the cavity: 2/3 < 0.7.
  shift(sim, kSac, Vec3(0, 0, -0.01));
  p.update(sim);
  EXPECT_NEAR(p.measures().sac_fraction, 16.0 / 24.0, 1e-12);
  EXPECT_EQ(p.step(TaskStep::kSacReduced).state, StepState::kActive);
  shift(sim, kSac, Vec3(0, 0, 0.002));  // 17.6 of 24 cm²: 0.733
  p.update(sim);
  EXPECT_NEAR(p.measures().sac_fraction, 17.6 / 24.0, 1e-12);
  EXPECT_EQ(p.step(TaskStep::kSacReduced).state, StepState::kDone);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kActive);
}

TEST(Task, MeshShiftedOneCentimetreFallsShortOfTheOverlap) {
  // The required disc: defect radius 1 cm + 3 cm overlap = 4 cm; the 9 cm mesh reaches 4.5 cm.
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  shift(sim, kMesh, Vec3(0.01, 0, 0));
  p.update(sim);  // step 1 done (the sac is all in the cavity)
  p.update(sim);
  EXPECT_LT(p.measures().coverage, 1);
  EXPECT_GT(p.measures().coverage, 0.95);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kActive);
  shift(sim, kMesh, Vec3(-0.01, 0, 0));
  p.update(sim);
  EXPECT_EQ(p.measures().coverage, 1);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kDone);
}

TEST(Task, TheMpoMustBeCoveredToo) {
  // An MPO reaching 4.8 cm to the right: beyond the 4.5 cm mesh.
  Scene scene = test::task_scene(R"("task": {"sac": "sac", "mesh": "mesh"})");
  scene.landmarks["mpo_0"] = Vec3(-0.03, -0.03, 0);
  scene.landmarks["mpo_1"] = Vec3(0.048, -0.03, 0);
  scene.landmarks["mpo_2"] = Vec3(0.048, 0.03, 0);
  scene.landmarks["mpo_3"] = Vec3(-0.03, 0.03, 0);
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  p.update(sim);
  p.update(sim);
  EXPECT_LT(p.measures().coverage, 1);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kActive);
  shift(sim, kMesh, Vec3(0.004, 0, 0));  // now 4.1 cm left of the defect, 4.9 cm right
  p.update(sim);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kDone);
}

TEST(Task, AFoldLargerThanTheLimitIsNotFlat) {
  Scene scene = test::task_scene(R"("task": {"sac": "sac", "mesh": "mesh", "max_fold_area": 2e-4, "overlap": 0})");
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  auto& x = sim.world().tissues[kMesh]->state.positions;
  const auto flat = x;
  for (Vec3& v : x)
    if (v.x() > 0.035 + 1e-9) v.x() = 0.07 - v.x();  // the last 1 cm folded back: 9 cm²
  p.update(sim);
  p.update(sim);
  EXPECT_NEAR(p.measures().fold_area, 0.01 * 0.09, 1e-12);
  EXPECT_EQ(p.measures().coverage, 1);  // the disc (1 cm) is covered; only the fold fails
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kActive);
  x = flat;
  // The edge's last 4 vertices (y ≥ 3 cm) folded back 1 cm: the 0.5 × 1.5 cm of cells between them
  // flip, and at most part of the 0.5 × 0.5 cm cell below: 0.75 to 1 cm².
  for (Vec3& v : x)
    if (v.x() > 0.04 + 1e-9 && v.y() > 0.025 + 1e-9) v.x() = 0.08 - v.x();
  p.update(sim);
  EXPECT_GE(p.measures().fold_area, 0.75e-4 - 1e-12);
  EXPECT_LE(p.measures().fold_area, 1.0e-4 + 1e-12);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kDone);
}

TEST(Task, MeshFixedNeedsFourHoldingTacksOnTheLandmarksAndNoneInAZone) {
  Scene scene = test::task_scene(R"("zones": [{"name": "doom", "polygon": [[0.03, -0.04, 0], [0.04, -0.04, 0], [0.035, -0.03, 0]]}],
    "task": {"sac": "sac", "mesh": "mesh"})");
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  p.update(sim);
  p.update(sim);
  ASSERT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kDone);
  const auto fire = [&](const Vec3& at) {
    put_tip(sim, at);
    p.fire_tacker(sim, 0);
    p.update(sim);
  };
  fire(Vec3(-0.02, 0.004, 0.0015));   // cooper (4.3 mm off)
  fire(Vec3(0.02, 0.0, 0.0015));      // medial
  fire(Vec3(0.0, 0.0, 0.0015));       // near none of them (2 cm from each)
  fire(Vec3(0.0, 0.05, 0.001));       // tissue only (the wall, 5 mm beyond the mesh's edge): not counted
  EXPECT_EQ(p.measures().fixed_tacks, 3);
  EXPECT_EQ(p.measures().landmarks_tacked, 2);
  EXPECT_EQ(p.step(TaskStep::kMeshFixed).state, StepState::kActive);
  fire(Vec3(0.0, 0.034, 0.0015));     // lateral, 1.4 cm off: within the 1.5 cm radius
  EXPECT_EQ(p.measures().fixed_tacks, 4);
  EXPECT_EQ(p.measures().landmarks_tacked, 3);
  EXPECT_EQ(p.step(TaskStep::kMeshFixed).state, StepState::kDone);
  EXPECT_TRUE(p.complete());
  EXPECT_EQ(p.error_count(), 0u);

  // The same four and one more in the zone: never complete, one error.
  Scene scene2 = test::task_scene(R"("zones": [{"name": "doom", "polygon": [[0.03, -0.04, 0], [0.04, -0.04, 0], [0.035, -0.03, 0]]}],
    "task": {"sac": "sac", "mesh": "mesh"})");
  Simulation sim2 = make_simulation(scene2);
  Procedure q(*scene2.task, sim2.world(), scene2.zones, scene2.landmarks);
  for (const Vec3& at : {Vec3(0.035, -0.036, 0.0015), Vec3(-0.02, 0, 0.0015), Vec3(0.02, 0, 0.0015), Vec3(0, 0.02, 0.0015),
                         Vec3(0, 0, 0.0015)}) {
    put_tip(sim2, at);
    q.fire_tacker(sim2, 0);
  }
  for (int k = 0; k < 3; ++k) q.update(sim2);
  EXPECT_EQ(q.measures().fixed_tacks, 4);
  EXPECT_EQ(q.measures().zone_tacks, 1);
  EXPECT_EQ(q.step(TaskStep::kMeshFixed).state, StepState::kActive);
  EXPECT_EQ(q.error_count(), 1u);
}

TEST(Task, StepsCompleteOnlyInOrder) {
  Scene scene = test::task_scene();
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  shift(sim, kSac, Vec3(0, 0, -0.03));  // the sac out of the cavity: step 1 cannot complete
  for (const Vec3& at : {Vec3(-0.02, 0, 0.0015), Vec3(0.02, 0, 0.0015), Vec3(0, 0.02, 0.0015), Vec3(0, 0, 0.0015)}) {
    put_tip(sim, at);
    p.fire_tacker(sim, 0);
  }
  for (int k = 0; k < 3; ++k) p.update(sim);
  EXPECT_EQ(p.step(TaskStep::kSacReduced).state, StepState::kActive);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kPending);
  EXPECT_EQ(p.step(TaskStep::kMeshFixed).state, StepState::kPending);
  EXPECT_EQ(p.measures().fixed_tacks, 4);  // counted for display all the same
  shift(sim, kSac, Vec3(0, 0, 0.03));
  p.update(sim);
  EXPECT_EQ(p.step(TaskStep::kSacReduced).state, StepState::kDone);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kActive);
  p.update(sim);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kDone);
  p.update(sim);
  EXPECT_TRUE(p.complete());
  const TaskView v = p.view();
  ASSERT_EQ(v.steps.size(), 3u);
  EXPECT_EQ(v.steps[2].name, "mesh fixed");
  EXPECT_EQ(v.steps[2].detail, "4 of 4 tacks; 3 of 3 landmarks; 0 in zones");
  EXPECT_TRUE(v.complete);
  std::size_t done_events = 0;
  for (const TaskEvent& e : p.events()) done_events += e.kind == TaskEventKind::kStepDone ? 1 : 0;
  EXPECT_EQ(done_events, 3u);
}

}  // namespace
}  // namespace trocar
