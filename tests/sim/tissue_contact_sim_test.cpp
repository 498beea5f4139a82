// The tissue–tissue contact inside Simulation: no work (bit for bit) without pairs, the scene's
// pairs and roll reach the solver, and the mesh on the wall stays above it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "mesh_on_wall_scene.h"
#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

TEST(TissueContactInSimulation, NoPairsIsBitIdenticalToTheIntegratorsAlone) {
  // A sheet falling freely under gravity through a Simulation (no instruments, no pairs) and the
  // same sheet stepped by its integrator alone: the same bits.
  const TriMesh sheet = make_sheet(0.05, 0.04, 10, 8, 0.005);
  MassSpringMaterial m;
  m.k_home = 0;
  World world;
  world.add_tissue("sheet", sheet, m, {}, Vec3(0, 0, -9.81), IntegratorKind::kImplicitEuler);
  Simulation sim(std::move(world), SimulationSettings{});
  TissueBody alone("sheet", sheet, m, {}, Vec3(0, 0, -9.81), IntegratorKind::kImplicitEuler);
  alone.loads.reset(alone.settings.vertex_count());
  for (int n = 0; n < 200; ++n) {
    sim.step(1e-3);
    alone.integrator.step(alone.state, alone.loads, 1e-3);
  }
  EXPECT_EQ(sim.world().tissues[0]->state.positions, alone.state.positions);
  EXPECT_EQ(sim.world().tissues[0]->state.velocities, alone.state.velocities);
  EXPECT_EQ(sim.tissue_contact().corrected(), 0u);
}

TEST(TissueContactInSimulation, SceneKeysReachTheSolver) {
  Scene scene = parse_scene(test::mesh_on_wall_scene(), "scene.json", ".");
  ASSERT_EQ(scene.settings.tissue_contacts.size(), 2u);
  EXPECT_EQ(scene.settings.tissue_contacts[0].a, 1u);
  EXPECT_EQ(scene.settings.tissue_contacts[0].b, 0u);
  EXPECT_DOUBLE_EQ(scene.settings.tissue_contacts[1].friction, 0.3);  // the default
  Simulation sim(std::move(scene.world), scene.settings);
  std::uint32_t corrected = 0;
  for (int n = 0; n < 300; ++n) {
    ASSERT_TRUE(sim.step(1e-3).finite);
    corrected += sim.tissue_contact().corrected();
  }
  EXPECT_GT(corrected, 0u);  // it landed
  Real lowest = 1;
  for (const Vec3& p : sim.world().tissues[1]->state.positions) lowest = std::min(lowest, p.z());
  Real wall_highest = -1;
  for (const Vec3& p : sim.world().tissues[0]->state.positions) wall_highest = std::max(wall_highest, p.z());
  EXPECT_GT(lowest, wall_highest);  // the wall sags under it, but the mesh stays above
}

/// The mesh-on-wall scene with both tissues XPBD (4 substeps) and the given "tissue_coupling".
std::string xpbd_mesh_on_wall(const std::string& coupling) {
  std::string text = test::mesh_on_wall_scene(false, "xpbd");
  if (!coupling.empty()) text.insert(text.rfind('}'), R"(, "tissue_coupling": ")" + coupling + "\"\n");
  return text;
}

TEST(TissueContactInSimulation, XpbdTissuesAreCoupledInsideTheirSubsteps) {
  // The same scene solved both ways: inside the substeps (the default for XPBD tissues) and after
  // the integrators. Both keep the mesh on the wall and come to rest (the coupled one measured
  // 2.3 mm/s at 0.3 s, the other 0.09 mm/s); they are different solves (different bits).
  struct Outcome {
    Real gap = 1, fastest = 0;
    std::vector<Vec3> mesh;
  };
  const auto run = [](const std::string& coupling) {
    Scene scene = parse_scene(xpbd_mesh_on_wall(coupling), "scene.json", ".");
    EXPECT_EQ(scene.settings.couple_tissues, coupling != "after");
    Simulation sim(std::move(scene.world), scene.settings);
    Outcome out;
    for (int n = 0; n < 300; ++n) EXPECT_TRUE(sim.step(1e-3).finite);
    const auto& wall = *sim.world().tissues[0];
    const auto& mesh = *sim.world().tissues[1];
    Real wall_highest = -1;
    for (const Vec3& p : wall.state.positions) wall_highest = std::max(wall_highest, p.z());
    for (const Vec3& p : mesh.state.positions) out.gap = std::min(out.gap, p.z() - wall_highest);
    for (const Vec3& v : mesh.state.velocities) out.fastest = std::max(out.fastest, v.norm());
    out.mesh = mesh.state.positions;
    return out;
  };
  const Outcome coupled = run(""), after = run("after");
  std::printf("xpbd mesh on wall after 0.3 s: coupled lowest %.3f mm over the wall's top, fastest %.3g m/s; "
              "after the integrators %.3f mm, %.3g m/s\n", 1e3 * coupled.gap, coupled.fastest, 1e3 * after.gap,
              after.fastest);
  EXPECT_GT(coupled.gap, 0);  // the wall sags under it, but the mesh stays above
  EXPECT_GT(after.gap, 0);
  EXPECT_NE(coupled.mesh, after.mesh);
  EXPECT_LT(coupled.fastest, 0.05);
  EXPECT_LT(after.fastest, 0.05);
}

TEST(TissueContactInSimulation, RollKeepsTheFlatSheetAsTheRestShape) {
  Scene scene = parse_scene(test::mesh_on_wall_scene(true), "scene.json", ".");
  const TissueBody& mesh = *scene.world.tissues[1];
  Real z_lo = 1, z_hi = -1;
  for (const Vec3& p : mesh.state.positions) z_lo = std::min(z_lo, p.z()), z_hi = std::max(z_hi, p.z());
  EXPECT_GT(z_hi - z_lo, 0.01);                        // rolled: about 2 cm tall
  EXPECT_NEAR(z_lo, 0.004, 1e-9);                      // resting on its former plane
  for (const Vec3& p : mesh.settings.rest_positions) EXPECT_DOUBLE_EQ(p.z(), 0.004);  // rest: flat
}

TEST(TissueContactInSimulation, BadContactKeysFailNamingTheKey) {
  const auto error_of = [](const std::string& text) {
    try {
      parse_scene(text, "scene.json", ".");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string text = test::mesh_on_wall_scene();
  std::string bad = text;
  bad.replace(bad.find(R"("b": "wall")"), 11, R"("b": "liver")");
  EXPECT_EQ(error_of(bad).rfind("scene.json: tissue_contacts[0].b: no tissue named \"liver\"", 0), 0u) << error_of(bad);
  bad = text;
  bad.replace(bad.find(R"("thickness": 0.001, "friction")"), 18, R"("thickness": -1)");
  EXPECT_EQ(error_of(bad).rfind("scene.json: tissue_contacts[0].thickness", 0), 0u) << error_of(bad);
  bad = test::mesh_on_wall_scene(true);
  bad.replace(bad.find(R"("axis": "y")"), 11, R"("axis": "z")");
  EXPECT_EQ(error_of(bad).rfind("scene.json: tissues[1].roll.axis", 0), 0u) << error_of(bad);
  bad = xpbd_mesh_on_wall("inside");
  EXPECT_EQ(error_of(bad).rfind("scene.json: tissue_coupling: must be \"substeps\" or \"after\"", 0), 0u)
      << error_of(bad);
}

}  // namespace
}  // namespace trocar
