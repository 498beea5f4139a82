// The XPBD solver against implicit Euler on small meshes: the same material gives the same
// static shape (a hanging sheet, a supported organ), the volume term keeps the volume under load,
// the colouring is a proper colouring, stiff light tissue stays stable (allocation_test.cpp checks
// that its step does not allocate).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "trocar/core/cpu_features.h"
#include "trocar/mesh/generate.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/xpbd.h"

namespace trocar {
namespace {

Real volume_of(const MassSpringSettings& s, const std::vector<Vec3>& x) {
  Real six_v = 0;
  for (const Triangle& t : s.triangles) six_v += x[t[0]].dot(x[t[1]].cross(x[t[2]]));
  return six_v / 6;
}

/// Runs `steps` steps of 1 ms and returns the final state.
MassSpringState settle(const MassSpringSettings& s, IntegratorKind kind, int steps, const TissueLoads* loads = nullptr,
                       int substeps = 4) {
  MassSpringIntegrator integrator(s, kind, {}, XpbdOptions{substeps});
  MassSpringState state = MassSpringState::at_rest(s);
  TissueLoads none;
  none.reset(s.vertex_count());
  for (int n = 0; n < steps; ++n) {
    const StepStats stats = integrator.step(state, loads ? *loads : none, 1e-3);
    EXPECT_TRUE(stats.finite);
    if (!stats.finite) break;
  }
  return state;
}

TEST(Xpbd, NameRoundTrips) {
  EXPECT_EQ(integrator_from_name("xpbd"), IntegratorKind::kXpbd);
  EXPECT_STREQ(integrator_name(IntegratorKind::kXpbd), "xpbd");
}

TEST(Xpbd, ColouringSharesNoVertexWithinAColour) {
  const TriMesh mesh = make_icosphere(0.05, 3);
  std::vector<std::uint32_t> ids;
  for (const Triangle& t : mesh.triangles) ids.insert(ids.end(), t.begin(), t.end());
  std::size_t colours = 0;
  const std::vector<std::uint32_t> colour = colour_items(ids, 3, mesh.vertex_count(), colours);
  ASSERT_EQ(colour.size(), mesh.triangles.size());
  // Each vertex touches at most one triangle of each colour.
  std::vector<std::vector<int>> seen(mesh.vertex_count(), std::vector<int>(colours, 0));
  for (std::size_t t = 0; t < colour.size(); ++t)
    for (const std::uint32_t v : mesh.triangles[t]) EXPECT_EQ(++seen[v][colour[t]], 1);
  // Greedy colouring needs at most (arity − 1)·(max items per vertex) + 1 colours: 6 per vertex here.
  EXPECT_LE(colours, 2u * 6 + 1);
  EXPECT_GE(colours, 3u);
}

// A sheet hanging from one edge under gravity: the static sag of its free edge under XPBD is the
// implicit solver's within 2 %, with the area term on.
TEST(Xpbd, HangingSheetSagMatchesImplicitEuler) {
  const TriMesh sheet = make_sheet(0.1, 0.1, 10, 10);
  MassSpringMaterial m;
  m.mass = 0.02;
  m.k_structural = 40;
  m.k_bending = 4;
  m.k_area = 5;
  m.damping = 20;  // settles within the run; the static shape does not depend on it
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0.0499, 0), Vec3(0, -1, 0)};  // the edge y = +5 cm
  const MassSpringSettings s = MassSpringSettings::build(sheet, m, fixed, Vec3(0, -9.81, 0));
  const MassSpringState implicit = settle(s, IntegratorKind::kImplicitEuler, 3000);
  const MassSpringState xpbd = settle(s, IntegratorKind::kXpbd, 3000);
  Real sag_implicit = 0, sag_xpbd = 0, rms = 0;
  for (std::size_t i = 0; i < s.vertex_count(); ++i) {
    sag_implicit = std::max(sag_implicit, s.rest_positions[i].y() - implicit.positions[i].y());
    sag_xpbd = std::max(sag_xpbd, s.rest_positions[i].y() - xpbd.positions[i].y());
    rms += (implicit.positions[i] - xpbd.positions[i]).squaredNorm();
  }
  rms = std::sqrt(rms / static_cast<Real>(s.vertex_count()));
  std::cout << "[ figures  ] hanging sheet sag: implicit " << sag_implicit * 1e3 << " mm, xpbd " << sag_xpbd * 1e3
            << " mm, rms difference " << rms * 1e3 << " mm\n";
  EXPECT_GT(sag_implicit, 0.001);
  EXPECT_NEAR(sag_xpbd, sag_implicit, 0.02 * sag_implicit);
  EXPECT_LT(rms, 0.02 * sag_implicit);
}

// A closed organ on a support (bottom fixed) under gravity and a press on its top: the top's
// sag matches implicit Euler within 2 % and the volume term keeps the volume within 1 % under load.
// (Without home springs a hollow sphere on its bottom cap leans on the volume term alone and
// creeps for seconds under implicit Euler: 10.9 mm at 3 s, 21.1 mm at 6 s; XPBD 21.1 and 21.6.)
TEST(Xpbd, SupportedOrganSagAndVolumeMatchImplicitEuler) {
  const TriMesh mesh = make_icosphere(0.04, 3);
  MassSpringMaterial m;
  m.mass = 0.3;
  m.k_structural = 300;
  m.k_bending = 30;
  m.k_area = 10;
  m.k_volume = 1e5;
  m.k_home = 5;  // an organ held in place (as the presets are): a well-posed static shape
  m.damping = 20;
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, -0.03), Vec3::UnitZ()};
  const MassSpringSettings s = MassSpringSettings::build(mesh, m, fixed, Vec3(0, 0, -9.81));
  TissueLoads loads;  // 2 N pressing down on the top cap
  loads.reset(s.vertex_count());
  std::vector<std::uint32_t> cap;
  for (std::size_t i = 0; i < s.vertex_count(); ++i)
    if (s.rest_positions[i].z() > 0.035) cap.push_back(static_cast<std::uint32_t>(i));
  ASSERT_FALSE(cap.empty());
  for (const std::uint32_t v : cap) loads.add_force(v, Vec3(0, 0, -2.0 / static_cast<Real>(cap.size())));
  const MassSpringState implicit = settle(s, IntegratorKind::kImplicitEuler, 4000, &loads);
  const MassSpringState xpbd = settle(s, IntegratorKind::kXpbd, 4000, &loads);
  const auto top_sag = [&](const MassSpringState& st) {
    Real sum = 0;
    for (const std::uint32_t v : cap) sum += s.rest_positions[v].z() - st.positions[v].z();
    return sum / static_cast<Real>(cap.size());
  };
  const Real sag_implicit = top_sag(implicit), sag_xpbd = top_sag(xpbd);
  const Real v_implicit = volume_of(s, implicit.positions) / s.rest_volume;
  const Real v_xpbd = volume_of(s, xpbd.positions) / s.rest_volume;
  std::cout << "[ figures  ] supported organ under 2 N: top sag implicit " << sag_implicit * 1e3 << " mm, xpbd "
            << sag_xpbd * 1e3 << " mm; V/V0 implicit " << v_implicit << ", xpbd " << v_xpbd << "\n";
  EXPECT_GT(sag_implicit, 0.001);
  EXPECT_NEAR(sag_xpbd, sag_implicit, 0.02 * sag_implicit);
  EXPECT_NEAR(v_xpbd, 1.0, 0.01);
  EXPECT_NEAR(v_implicit, 1.0, 0.01);
}

// Stiff springs on a light organ (k 5,000 N/m, 50 g): no divergence and no energy growth at rest
// after a perturbation, for 1 to 8 substeps.
TEST(Xpbd, StiffLightOrganStaysStableAndLosesEnergy) {
  const TriMesh mesh = make_icosphere(0.05, 3);
  MassSpringMaterial m;
  m.mass = 0.05;
  m.k_structural = 5000;
  m.k_bending = 500;
  m.k_area = 10;
  m.k_volume = 100;
  const MassSpringSettings s = MassSpringSettings::build(mesh, m);
  for (const int substeps : {1, 4, 8}) {
    MassSpringIntegrator integrator(s, IntegratorKind::kXpbd, {}, XpbdOptions{substeps});
    MassSpringState state = MassSpringState::at_rest(s);
    for (std::size_t i = 0; i < state.positions.size(); ++i)  // a 2 mm dent and a kick
      state.positions[i] *= 1 + 0.04 * std::sin(7.0 * static_cast<double>(i));
    TissueLoads none;
    none.reset(s.vertex_count());
    Real first = -1, last = 0;
    for (int n = 0; n < 500; ++n) {
      const StepStats stats = integrator.step(state, none, 1e-3);
      ASSERT_TRUE(stats.finite) << substeps << " substeps, step " << n;
      const Real e = kinetic_energy(s, state.velocities) + potential_energy(s, state.positions, ForceTerms{});
      if (n == 10) first = e;
      last = e;
    }
    EXPECT_LT(last, first) << substeps << " substeps";
  }
}

TEST(Xpbd, FixedVerticesStayBitForBit) {
  const TriMesh sheet = make_sheet(0.1, 0.1, 8, 8);
  MassSpringMaterial m;
  m.mass = 0.02;
  m.k_area = 5;
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0.0499, 0), Vec3(0, -1, 0)};
  const MassSpringSettings s = MassSpringSettings::build(sheet, m, fixed, Vec3(0, -9.81, 0));
  MassSpringIntegrator integrator(s, IntegratorKind::kXpbd);
  MassSpringState state = MassSpringState::at_rest(s);
  TissueLoads loads;
  loads.reset(s.vertex_count());
  for (int n = 0; n < 50; ++n) {
    loads.clear();
    loads.add_force(3, Vec3(0, 0, 0.01));
    integrator.step(state, loads, 1e-3);
  }
  for (std::size_t i = 0; i < s.vertex_count(); ++i) {
    if (!s.fixed[i]) continue;
    EXPECT_EQ(state.positions[i], s.rest_positions[i]);
    EXPECT_EQ(state.velocities[i], Vec3::Zero());
  }
}

/// Records what the contacts see at the start of each step: the largest |x − previous| (m).
struct MotionSeen : XpbdContacts {
  std::vector<Real> largest;
  void begin_step(const XpbdView& view, int) override {
    Real most = 0;
    for (std::size_t v = 0; v < view.x.size(); ++v) {
      const Vec3 d(view.x[v].x - view.previous[v].x, view.x[v].y - view.previous[v].y, view.x[v].z - view.previous[v].z);
      most = std::max(most, d.norm());
    }
    largest.push_back(most);
  }
  void solve(const XpbdView&, int, int, Real) override {}
  void solve_velocities(std::span<XpbdParticle>) override {}
};

TEST(Xpbd, ASolverBuiltForADeformedMovingTissueStartsFromItsTrueMotion) {
  // A cut rebuilds the solver for a tissue that is deformed and moving. Its first step must see
  // the motion of the state (x − v h: |v| h), not a jump from the rest shape (1 cm here), which
  // would open the contacts' reach to its widest.
  const TriMesh sheet = make_sheet(0.1, 0.1, 8, 8);
  MassSpringMaterial m;
  m.mass = 0.02;
  const MassSpringSettings s = MassSpringSettings::build(sheet, m, FixedSelection{}, Vec3::Zero());
  XpbdSolver solver(s, XpbdOptions{4});
  MassSpringState state = MassSpringState::at_rest(s);
  for (std::size_t i = 0; i < s.vertex_count(); ++i) {
    state.positions[i].z() += 0.01;
    state.velocities[i] = Vec3(0, 0, 0.2);
  }
  TissueLoads none;
  none.reset(s.vertex_count());
  MotionSeen seen;
  solver.step(state, none, 1e-3, &seen);
  solver.step(state, none, 1e-3, &seen);
  ASSERT_EQ(seen.largest.size(), 2u);
  EXPECT_NEAR(seen.largest[0], 0.2 * 1e-3 / 4, 1e-7);  // |v| h, h = dt / 4 substeps
  EXPECT_NEAR(seen.largest[1], 0.2 * 1e-3 / 4, 1e-7);  // and so on: the last substep's motion
}

// The 8-lane AVX2 passes and the scalar passes run the same arithmetic in the same colour order:
// one step agrees to float rounding, 100 steps of a perturbed organ with every term on to 1 % of
// the motion.
TEST(Xpbd, Avx2PassesAgreeWithScalarPasses) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "no AVX2/FMA here";
  const TriMesh mesh = make_icosphere(0.05, 3);
  MassSpringMaterial m;
  m.mass = 0.2;
  m.k_structural = 200;
  m.k_bending = 20;
  m.k_area = 10;
  m.k_volume = 1000;
  m.k_home = 2;
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, -0.04), Vec3::UnitZ()};
  const MassSpringSettings s = MassSpringSettings::build(mesh, m, fixed, Vec3(0, 0, -9.81));
  MassSpringIntegrator simd(s, IntegratorKind::kXpbd), scalar(s, IntegratorKind::kXpbd);
  scalar.xpbd()->set_simd(false);
  ASSERT_TRUE(simd.xpbd()->simd());
  MassSpringState a = MassSpringState::at_rest(s), b = a;
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    if (!s.fixed[i]) a.positions[i].z() += 0.003 * std::sin(3.0 * static_cast<double>(i));
  b = a;
  TissueLoads none;
  none.reset(s.vertex_count());
  Real moved = 0, differ = 0, first = 0;
  for (int n = 0; n < 100; ++n) {
    simd.step(a, none, 1e-3);
    scalar.step(b, none, 1e-3);
    if (n == 0)
      for (std::size_t i = 0; i < a.positions.size(); ++i) first = std::max(first, (a.positions[i] - b.positions[i]).norm());
  }
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    moved = std::max(moved, (a.positions[i] - s.rest_positions[i]).norm());
    differ = std::max(differ, (a.positions[i] - b.positions[i]).norm());
  }
  std::cout << "[ figures  ] AVX2 vs scalar: max difference after 1 step " << first * 1e9 << " nm, after 100 steps "
            << differ * 1e6 << " µm (moved " << moved * 1e3 << " mm)\n";
  // FMA contraction and the order of float sums differ; a chaotic 100-step run amplifies it.
  EXPECT_GT(moved, 1e-3);
  EXPECT_LT(first, 1e-7);
  EXPECT_LT(differ, 0.01 * moved);
}

}  // namespace
}  // namespace trocar

namespace trocar {
namespace {

// Coagulation changes springs in place (XpbdSolver::springs_changed): the solver then steps exactly
// as one built from the changed settings.
TEST(XpbdSpringsChanged, InPlaceUpdateStepsAsAFreshSolver) {
  const TriMesh sheet = make_sheet(0.04, 0.04, 8, 8);
  MassSpringMaterial m = material_preset("peritoneum");
  FixedSelection fixed;
  fixed.indices = {0, 8, 72, 80};
  MassSpringSettings changed = MassSpringSettings::build(sheet, m, fixed, Vec3(0, 0, -9.81));
  const MassSpringSettings original = changed;
  MassSpringIntegrator in_place(changed, IntegratorKind::kXpbd);
  std::vector<std::uint32_t> list;
  for (std::uint32_t s = 10; s < 60; s += 7) {
    changed.springs[s].stiffness *= 3;
    changed.springs[s].rest_length *= 0.9;
    list.push_back(s);
  }
  ASSERT_TRUE(in_place.springs_changed(list));
  MassSpringIntegrator fresh(changed, IntegratorKind::kXpbd);
  MassSpringState a = MassSpringState::at_rest(changed), b = a;
  TissueLoads loads;
  loads.reset(changed.vertex_count());
  for (int n = 0; n < 50; ++n) {
    in_place.step(a, loads, 1e-3);
    fresh.step(b, loads, 1e-3);
  }
  for (std::size_t v = 0; v < a.positions.size(); ++v) ASSERT_EQ(a.positions[v], b.positions[v]) << v;
  // And the change moved something (the test would pass vacuously otherwise).
  MassSpringIntegrator unchanged(original, IntegratorKind::kXpbd);
  MassSpringState c = MassSpringState::at_rest(original);
  for (int n = 0; n < 50; ++n) unchanged.step(c, loads, 1e-3);
  Real moved = 0;
  for (std::size_t v = 0; v < a.positions.size(); ++v) moved = std::max(moved, (a.positions[v] - c.positions[v]).norm());
  EXPECT_GT(moved, 1e-5);
}

}  // namespace
}  // namespace trocar
