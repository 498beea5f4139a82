// No heap allocation inside Simulation::step after the first steps (docs/architecture.md
// "Conventions"): a counting global operator new (for this whole test binary; it counts only while
// a window is open).
#include <gtest/gtest.h>

#include "support/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

#include "mesh_on_wall_scene.h"
#include "probe_scene.h"
#include "sheet_scene.h"
#include "trocar/response/contact_projection.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/robustness.h"

using trocar::test::g_allocations;
using trocar::test::g_counting;

namespace trocar {
namespace {

/// Runs 150 steps (the buffers reach their size), then counts the heap allocations of the next
/// 100; every step detects and measures. Returns the contacts seen while counting.
std::uint32_t expect_no_allocation(Scene scene) {
  Simulation sim(std::move(scene.world), scene.settings);
  for (int n = 0; n < 150; ++n) sim.step(1e-3);
  g_allocations = 0;
  g_counting = true;
  std::uint32_t contacts = 0;
  for (int n = 0; n < 100; ++n) contacts += sim.step(1e-3).contacts;
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  return contacts;
}

TEST(SimulationAllocation, StepInContactAllocatesNothing) {
  ASSERT_EQ(test::probe_counted_allocations(), 2);  // the counting operator new is in use
  // A probe pressed into a closed ball for 0.1 s, then held.
  EXPECT_GT(expect_no_allocation(test::probe_scene(0.04, 0.024, 0.1)), 0u);
}

TEST(SimulationAllocation, StepThroughASheetAllocatesNothing) {
  // The open-tissue metrics (sheet side and crossing checks, sheet_crossing.cpp): pressed 4 mm
  // into the sheet for 0.1 s, then held.
  Scene scene = parse_scene(test::sheet_scene("[0.001, 0.002, 0.002]", "[0.001, 0.002, -0.002]", 0.1, 0.001),
                            "sheet.json", ".");
  ASSERT_TRUE(scene.settings.measure_penetration);
  EXPECT_GT(expect_no_allocation(std::move(scene)), 0u);
}

TEST(SimulationAllocation, SdfProjectionAllocatesNothingFromItsFirstContact) {
  // The sdf response's projector, sized at construction (reset, size_for): the hook probe pressed
  // into the suite's 2K lobe; counting from the step before the first contact to the end of the
  // press, the projector's own calls allocate nothing (the detector's contact list may still
  // grow while the contact count rises: counted apart, in StepInContactAllocatesNothing).
  const std::vector<SuiteOrgan> family = generated_organs(1);
  Real duration = 0;
  World world = suite_world(family.front(), SuiteMotion::kPress, duration);
  TissueBody& tissue = *world.tissues.front();
  const InstrumentBody& body = world.instruments.front();
  const InstrumentField field(body.instrument.local_mesh());
  ContactProjector projector;
  projector.reset(tissue.settings.vertex_count(), tissue.settings.triangles, body.instrument.world_positions().size());
  projector.size_for(field);
  Grasp grasp;
  grasp.reset(tissue.settings.vertex_count());
  KeyframeMotion motion = body.motion;
  Instrument tool = body.instrument;
  const ResponseSettings settings = suite_settings(ResponseMethod::kSdf).response;
  const ProjectedTissue view{tissue.state.positions, tissue.state.velocities, tissue.settings.masses,
                             tissue.settings.fixed, tissue.settings.triangles};
  std::uint32_t projected = 0;
  g_allocations = 0;
  g_counting = true;
  for (int n = 1; n <= static_cast<int>(duration / 1e-3); ++n) {
    const MotionSample s = motion.sample(n * 1e-3);
    tool.move_to(s.pose, 1e-3);
    projected += projector.project(tool, field, {}, 0, 1, grasp, view, body.thickness, 1e-3, settings).projected;
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(projected, 10u);  // measured 35 (the tissue is not integrated here: it stays where pushed)
}

TEST(SimulationAllocation, MeshOnAWallAllocatesNothing) {
  // Tissue–tissue contact (the triangle grid, the candidate list): the mesh lands on the wall and
  // rests (response/tissue_contact.h). A tack on this light mesh is left out: its first pull
  // shakes the mesh for long (docs/response.md, "Tissue against tissue", known limits).
  // Both ways: after implicit Euler, and inside the substeps of XPBD tissues in lock-step.
  for (const char* integrator : {"implicit-euler", "xpbd"}) {
    Scene scene = parse_scene(test::mesh_on_wall_scene(false, integrator), "mesh.json", ".");
    Simulation sim(std::move(scene.world), scene.settings);
    for (int n = 0; n < 150; ++n) sim.step(1e-3);
    g_allocations = 0;
    g_counting = true;
    std::uint32_t corrected = 0;
    for (int n = 0; n < 100; ++n) {
      sim.step(1e-3);
      corrected += sim.tissue_contact().corrected();
    }
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << integrator;
    EXPECT_GT(corrected, 0u) << integrator;
  }
}

}  // namespace
}  // namespace trocar

#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"

namespace trocar {
namespace {

TEST(SimulationAllocation, BurningAndCoagulatingWithoutACutAllocatesNothing) {
  // The live hook at 10 W drawn over a peritoneum at 20 mm/s: every 2 mm cell under it coagulates
  // (its springs stiffened in place) but is left before it boils off. It goes out and back along
  // the same path: the outward pass (burning only at its end, so that the first coagulation is
  // behind it) brings the contact's buffers to their size; the return pass is counted.
  World world;
  FixedSelection fixed;
  const TriMesh sheet = make_sheet(0.04, 0.04, 20, 20);
  for (std::uint32_t v = 0; v < sheet.positions.size(); ++v)
    if (std::abs(sheet.positions[v].x()) > 0.0199 || std::abs(sheet.positions[v].y()) > 0.0199) fixed.indices.push_back(v);
  world.add_tissue("sheet", sheet, material_preset("peritoneum"), fixed, Vec3(0, 0, -9.81), IntegratorKind::kXpbd);
  const Quat q(Eigen::AngleAxis<Real>(1.5707963267948966, Vec3::UnitZ()));
  world.add_instrument("hook", Instrument(make_hook_probe().mesh, Vec3::UnitZ()),
                       KeyframeMotion({{0, Vec3(0, -0.015, -0.0003), q, 0}, {1.5, Vec3(0, 0.01, -0.0003), q, 0},
                                       {3.0, Vec3(0, -0.015, -0.0003), q, 0}}))
      .electrode.power = 10;
  Simulation sim(std::move(world), SimulationSettings{});
  for (int n = 0; n < 1500; ++n) {
    sim.set_energy(0, n >= 1100);
    sim.step(1e-3);
  }
  ASSERT_GT(sim.world().tissues[0]->model_version, 0u);  // coagulated once already
  const std::uint32_t version = sim.world().tissues[0]->model_version;
  g_allocations = 0;
  g_counting = true;
  Real energy = 0;
  for (int n = 0; n < 1500; ++n) energy += sim.step(1e-3).energy;
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(energy, 13.0);                                            // it burnt all along (15 J)
  EXPECT_GT(sim.world().tissues[0]->model_version, version + 5);      // coagulating as it went
  EXPECT_EQ(sim.burn_tally(0).cut_triangles, 0u);                     // never a cut (a rebuild)
}

}  // namespace
}  // namespace trocar
