// Procedure::update allocates nothing after its first evaluations while it logs nothing, whichever
// step is active (docs/procedure.md "Hooks").
#include <gtest/gtest.h>

#include "procedure/task_scene.h"
#include "support/allocation_counter.h"
#include "trocar/procedure/procedure.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

constexpr std::size_t kMesh = 1, kSac = 2;

void shift(Simulation& sim, std::size_t tissue, const Vec3& by) {
  for (Vec3& x : sim.world().tissues[tissue]->state.positions) x += by;
}

/// Allocations of 20 updates.
long count_updates(Procedure& p, const Simulation& sim) {
  test::g_allocations = 0;
  test::g_counting = true;
  for (int k = 0; k < 20; ++k) p.update(sim);
  test::g_counting = false;
  return test::g_allocations.load();
}

TEST(ProcedureAllocation, UpdateAllocatesNothingWhileItLogsNothing) {
  ASSERT_EQ(test::probe_counted_allocations(), 2);  // the counting operator new is in use
  Scene scene = test::task_scene(R"("zones": [{"name": "doom", "polygon": [[0.03, -0.04, 0], [0.04, -0.04, 0], [0.035, -0.03, 0]]}],
    "task": {"sac": "sac", "mesh": "mesh"})");
  Simulation sim = make_simulation(scene);
  Procedure p(*scene.task, sim.world(), scene.zones, scene.landmarks);
  drive(sim, scene.timestep, 5);
  shift(sim, kSac, Vec3(0, 0, -0.03));  // step 1 active and failing
  p.update(sim);
  EXPECT_EQ(count_updates(p, sim), 0);
  EXPECT_EQ(p.step(TaskStep::kSacReduced).state, StepState::kActive);

  shift(sim, kSac, Vec3(0, 0, 0.03));
  shift(sim, kMesh, Vec3(0.02, 0, 0));  // step 2 active and failing
  p.update(sim);                        // logs step 1
  EXPECT_EQ(count_updates(p, sim), 0);
  EXPECT_EQ(p.step(TaskStep::kMeshPlaced).state, StepState::kActive);

  shift(sim, kMesh, Vec3(-0.02, 0, 0));
  p.update(sim);  // logs step 2
  Pose pose;
  pose.translation = Vec3(-0.02, 0, 0.004);
  sim.place_instrument(0, pose, 0);
  p.fire_tacker(sim, 0);
  EXPECT_EQ(count_updates(p, sim), 0);  // step 3 active: 1 of 4 tacks
  EXPECT_EQ(p.step(TaskStep::kMeshFixed).state, StepState::kActive);
  EXPECT_EQ(p.measures().fixed_tacks, 1);
}

}  // namespace
}  // namespace trocar
