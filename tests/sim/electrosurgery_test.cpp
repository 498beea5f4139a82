// Electrosurgery through the simulation's step (docs/electrosurgery.md): a live hook on a sheet
// coagulates and cuts it, the cut tissue stays finite and manifold, and an incision's edges part.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"
#include "trocar/mesh/topology.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

/// A hook whose foot lies along +y (the way it is drawn), its lowest point `height` over z = 0.
Quat foot_along_y() { return Quat(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitZ())); }

struct HookOnSheet {
  Simulation sim;
  static World make(Real width, std::size_t cells, Real power, std::vector<Keyframe> keys) {
    World world;
    const TriMesh sheet = make_sheet(width, width, cells, cells);
    MassSpringMaterial m = material_preset("peritoneum");
    FixedSelection fixed;  // the border is held
    const Real h = width / 2 - 1e-6;
    for (std::uint32_t v = 0; v < sheet.positions.size(); ++v)
      if (std::abs(sheet.positions[v].x()) > h || std::abs(sheet.positions[v].y()) > h) fixed.indices.push_back(v);
    world.add_tissue("sheet", sheet, m, fixed, Vec3(0, 0, -9.81), IntegratorKind::kXpbd);
    InstrumentMesh hook = make_hook_probe();
    InstrumentBody& body = world.add_instrument("hook", Instrument(hook.mesh, Vec3::UnitZ()), KeyframeMotion(std::move(keys)));
    body.tool = "hook-probe";
    body.electrode.power = power;
    return world;
  }
  HookOnSheet(Real width, std::size_t cells, Real power, std::vector<Keyframe> keys)
      : sim(make(width, cells, power, std::move(keys)), SimulationSettings{}) {}
};

/// Edges used by more than two triangles, and vertices whose triangles form more than one fan.
std::size_t non_manifold(const MassSpringSettings& s) {
  TriMesh mesh;
  mesh.positions = s.rest_positions;
  mesh.triangles = s.triangles;
  const MeshTopology topology(mesh);
  return topology.nonmanifold_edges().size() + topology.nonmanifold_vertices().size();
}

TEST(Electrosurgery, AHookHeldOnASheetCoagulatesThenCutsItOpen) {
  const Quat q = foot_along_y();
  HookOnSheet scene(0.04, 20, 40.0, {{0, Vec3(0, 0, 0.0002), q, 0}});
  Simulation& sim = scene.sim;
  for (int n = 0; n < 100; ++n) sim.step(1e-3);  // settles under the hook, pedal up: no heat
  EXPECT_EQ(sim.thermal(0).delivered(), 0.0);
  sim.set_energy(0, true);
  Real first_cut = -1, first_coag = -1;
  const std::size_t triangles = sim.world().tissues[0]->settings.triangles.size();
  for (int n = 0; n < 2000; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite);
    if (first_coag < 0 && sim.burn_tally(0).coagulated_area > 0) first_coag = sim.time();
    if (first_cut < 0 && m.triangles_cut > 0) first_cut = sim.time();
  }
  const BurnTally tally = sim.burn_tally(0);
  std::printf("coagulated at %.3f s, first cut at %.3f s; %u triangles cut (%.1f mm²), coagulated %.1f mm², %.2f J\n",
              first_coag, first_cut, tally.cut_triangles, 1e6 * tally.cut_area, 1e6 * tally.coagulated_area, tally.energy);
  EXPECT_GT(first_coag, 0.1);
  EXPECT_GT(first_cut, first_coag);
  EXPECT_GT(tally.cut_triangles, 0u);
  EXPECT_EQ(sim.world().tissues[0]->settings.triangles.size(), triangles - tally.cut_triangles);
  EXPECT_EQ(non_manifold(sim.world().tissues[0]->settings), 0u);
}

}  // namespace
}  // namespace trocar
