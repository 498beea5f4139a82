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

TEST(Electrosurgery, CoagulatedTrianglesStiffenTheirSpringsAtTheirPresentLength) {
  const Quat q = foot_along_y();
  // Held still, then moved 2 mm sideways at 0.15 s: the new place's triangles share edges with
  // the first burn's.
  HookOnSheet scene(0.04, 20, 40.0,
                    {{0, Vec3(0, 0, -0.0005), q, 0}, {0.15, Vec3(0, 0, -0.0005), q, 0},
                     {0.2, Vec3(0.002, 0, -0.0005), q, 0}});
  Simulation& sim = scene.sim;
  for (int n = 0; n < 100; ++n) sim.step(1e-3);
  const MassSpringSettings before = sim.world().tissues[0]->settings;  // a copy: the model is replaced
  sim.set_energy(0, true);
  int steps = 0;
  while (sim.world().tissues[0]->model_version == 0 && steps < 200) {
    sim.step(1e-3);
    ++steps;
  }
  ASSERT_EQ(sim.world().tissues[0]->model_version, 1u) << "coagulated within 0.2 s";
  // The remodel at the end of that step: each spring of a newly coagulated triangle is 3× as
  // stiff and at rest at the length it has now; every other spring is as it was.
  {
    const TissueBody& sheet = *sim.world().tissues[0];
    ASSERT_EQ(sheet.settings.springs.size(), before.springs.size());
    std::size_t stiffened = 0;
    for (std::size_t s = 0; s < before.springs.size(); ++s) {
      const Spring& was = before.springs[s];
      const Spring& now = sheet.settings.springs[s];
      if (now.stiffness != was.stiffness) {
        ++stiffened;
        EXPECT_LT(s, before.structural_count);
        EXPECT_DOUBLE_EQ(now.stiffness, 3 * was.stiffness);
        EXPECT_EQ(now.rest_length, (sheet.state.positions[now.i] - sheet.state.positions[now.j]).norm());
      } else {
        EXPECT_EQ(now.rest_length, was.rest_length);
      }
    }
    EXPECT_GE(stiffened, 3u);  // at least one triangle's three edges
  }
  // Burning on at the new place (nothing cut yet): more triangles coagulate, no spring is
  // stiffened twice.
  for (int n = 0; n < 150; ++n) sim.step(1e-3);
  sim.set_energy(0, false);
  const TissueBody& sheet = *sim.world().tissues[0];
  ASSERT_EQ(sim.burn_tally(0).cut_triangles, 0u);
  EXPECT_GT(sheet.model_version, 1u);
  for (std::size_t s = 0; s < before.springs.size(); ++s)
    EXPECT_LE(sheet.settings.springs[s].stiffness, 3 * before.springs[s].stiffness * (1 + 1e-12));
}

TEST(Electrosurgery, DraggingTheLiveHookMakesAnIncisionAlongItsPath) {
  // 3 cm along y at 5 mm/s, the foot 0.2 mm into the sheet, over a 4 cm sheet of 2 mm cells.
  const Quat q = foot_along_y();
  HookOnSheet scene(0.04, 20, 40.0, {{0, Vec3(0, -0.015, -0.0002), q, 0}, {6.0, Vec3(0, 0.015, -0.0002), q, 0}});
  Simulation& sim = scene.sim;
  sim.set_energy(0, true);
  int steps_cutting = 0;
  for (int n = 0; n < 6000; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite) << sim.time();
    steps_cutting += m.triangles_cut > 0 ? 1 : 0;
  }
  const TissueBody& sheet = *sim.world().tissues[0];
  // The removed triangles lie along the path: the holes' rest centroids within 3 mm of x = 0,
  // spanning y from about −15 to +15 mm.
  std::set<std::uint32_t> kept;
  Real y_lo = 1, y_hi = -1;
  const TriMesh original = make_sheet(0.04, 0.04, 20, 20);
  std::vector<int> used(original.triangles.size(), 0);
  // Match kept triangles to the original ones by their rest corners (cut keeps rest positions).
  for (const Triangle& t : sheet.settings.triangles) {
    const Vec3 c = (sheet.settings.rest_positions[t[0]] + sheet.settings.rest_positions[t[1]] +
                    sheet.settings.rest_positions[t[2]]) / 3;
    for (std::size_t k = 0; k < original.triangles.size(); ++k) {
      const Triangle& o = original.triangles[k];
      const Vec3 oc = (original.positions[o[0]] + original.positions[o[1]] + original.positions[o[2]]) / 3;
      if ((oc - c).norm() < 1e-9) used[k] = 1;
    }
  }
  std::size_t removed = 0;
  for (std::size_t k = 0; k < original.triangles.size(); ++k) {
    if (used[k]) continue;
    ++removed;
    const Triangle& o = original.triangles[k];
    const Vec3 oc = (original.positions[o[0]] + original.positions[o[1]] + original.positions[o[2]]) / 3;
    EXPECT_LT(std::abs(oc.x()), 0.003) << oc.transpose();
    y_lo = std::min(y_lo, oc.y());
    y_hi = std::max(y_hi, oc.y());
  }
  const BurnTally tally = sim.burn_tally(0);
  std::printf("incision: %zu triangles removed, y %.1f to %.1f mm, %d steps cut, %.1f J, %.0f mm² coagulated\n",
              removed, 1e3 * y_lo, 1e3 * y_hi, steps_cutting, tally.energy, 1e6 * tally.coagulated_area);
  EXPECT_EQ(removed, tally.cut_triangles);
  EXPECT_LT(y_lo, -0.012);
  EXPECT_GT(y_hi, 0.012);
  EXPECT_EQ(non_manifold(sheet.settings), 0u);
}

TEST(Electrosurgery, AnIncisionAcrossAStretchedSheetPartsByTheStretch) {
  // A sheet at rest 40/1.1 mm wide (x) and 40 mm tall (y), stretched 10 % in x between its fixed
  // left and right borders, no gravity, no home springs. Cut across its whole height at x = 0,
  // each half is free but for its border and relaxes to its rest shape: a vertex of rest x_r on
  // the left ends at −20 mm + (x_r + W0/2), on the right at 20 mm − (W0/2 − x_r). The incision
  // parts by the stretch, 0.1 W0 = 3.64 mm, plus the burnt strip's rest width. Coagulation does
  // not change the springs here.
  const Real stretch = 1.1, width = 0.04, rest_width = width / stretch;
  const TriMesh rest = make_sheet(rest_width, width, 20, 20);
  MassSpringMaterial m = material_preset("peritoneum");
  m.k_home = 0;
  FixedSelection fixed;
  for (std::uint32_t v = 0; v < rest.positions.size(); ++v)
    if (std::abs(rest.positions[v].x()) > rest_width / 2 - 1e-9) fixed.indices.push_back(v);
  World world;
  world.tissues.push_back(std::make_unique<TissueBody>(
      "sheet", MassSpringSettings::build(rest, m, fixed, Vec3::Zero()), IntegratorKind::kXpbd, ImplicitOptions{},
      XpbdOptions{}));
  TissueBody& body = *world.tissues[0];
  for (Vec3& x : body.state.positions) x.x() *= stretch;
  // Coagulation would fix the burnt margin's springs at their stretched length (its own test).
  body.coagulation_stiffening = 1;
  const Quat q = foot_along_y();
  InstrumentMesh hook = make_hook_probe();
  InstrumentBody& h = world.add_instrument(
      "hook", Instrument(hook.mesh, Vec3::UnitZ()),
      KeyframeMotion({{0, Vec3(0, -0.026, -0.0002), q, 0}, {10.0, Vec3(0, 0.022, -0.0002), q, 0},
                      {10.5, Vec3(0, 0.022, 0.02), q, 0}}));
  h.electrode.power = 40;
  Simulation sim(std::move(world), SimulationSettings{});
  sim.set_energy(0, true);
  for (int n = 0; n < 10500; ++n) ASSERT_TRUE(sim.step(1e-3).finite) << sim.time();
  sim.set_energy(0, false);
  for (int n = 0; n < 3000; ++n) ASSERT_TRUE(sim.step(1e-3).finite) << sim.time();
  const TissueBody& cut = *sim.world().tissues[0];
  TriMesh mesh;
  mesh.positions = cut.settings.rest_positions;
  mesh.triangles = cut.settings.triangles;
  const MeshTopology topology(mesh);
  ASSERT_EQ(topology.component_count(), 2u);  // cut through
  // Each vertex's side: its piece's (the component of its triangles), named by the piece's border.
  std::vector<int> left_piece(topology.component_count(), 0);
  for (std::size_t v = 0; v < cut.state.positions.size(); ++v)
    if (cut.settings.rest_positions[v].x() < -rest_width / 2 + 1e-9)
      left_piece[topology.triangle_component(topology.vertex_triangles(v)[0])] = 1;
  // Relaxed, each piece is its rest shape hinged on its fixed border (a flat piece may turn about
  // that line: nothing but bending resists it without gravity): a vertex's distance from the
  // border line (x = ∓20 mm, z = 0) is its rest distance from that border.
  Real worst = 0, left_edge = -1, right_edge = 1;
  for (std::size_t v = 0; v < cut.state.positions.size(); ++v) {
    const Real xr = cut.settings.rest_positions[v].x();
    const Vec3& x = cut.state.positions[v];
    const bool left = left_piece[topology.triangle_component(topology.vertex_triangles(v)[0])] != 0;
    const Real border = left ? -width / 2 : width / 2;
    const Real distance = std::hypot(x.x() - border, x.z());
    const Real expected = left ? xr + rest_width / 2 : rest_width / 2 - xr;
    worst = std::max(worst, std::abs(distance - expected));
    if (std::abs(x.y()) < 0.005) {
      if (left) left_edge = std::max(left_edge, x.x());
      else right_edge = std::min(right_edge, x.x());
    }
  }
  std::printf("parted: opening %.2f mm at mid-height (stretch alone %.2f mm), worst vertex %.3f mm from its "
              "relaxed place, %u triangles cut\n", 1e3 * (right_edge - left_edge), 1e3 * (width - rest_width),
              1e3 * worst, sim.burn_tally(0).cut_triangles);
  EXPECT_LT(worst, 3e-4);
  EXPECT_GT(right_edge - left_edge, width - rest_width);
}

}  // namespace
}  // namespace trocar
