// Plastic home springs through the simulation's step (docs/tissue.md "Home springs"): a tissue held
// by its home springs against a steady load sags k_home-elastically when the load stays within
// the yield and creeps on when it does not, under the semi-implicit, implicit and XPBD integrators.
#include <gtest/gtest.h>

#include <cstdio>

#include "trocar/mesh/generate.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

/// The sag (m, mean over the vertices along gravity) of a free sheet held by its home springs
/// alone under gravity g, after `seconds`, stepped by a Simulation: elastic, m_i g / k_home.
Real sag(IntegratorKind kind, Real yield, Real seconds) {
  const TriMesh sheet = make_sheet(0.04, 0.04, 8, 8);
  MassSpringMaterial m;
  m.mass = 0.0162;  // 0.2 g a vertex: m g / k_home = 0.2e-3 · 10 / 1 = 2 mm
  m.k_home = 1;
  m.home_yield = yield;
  m.damping = 20;   // settles within a second
  // Springs and dashpots soft enough for the explicit integrator at 1 ms on the lightest (corner)
  // vertex, 0.04 g: h² k / m = 0.25, h λ / m = 0.025.
  m.k_structural = 10;
  m.k_bending = 1;
  m.spring_damping = 0.001;
  World world;
  world.add_tissue("sheet", sheet, m, {}, Vec3(0, 0, -10), kind);
  Simulation sim(std::move(world), SimulationSettings{});
  const int steps = static_cast<int>(seconds / 1e-3 + 0.5);
  for (int n = 0; n < steps; ++n) sim.step(1e-3);
  const TissueBody& t = *sim.world().tissues[0];
  Real sum = 0;
  for (std::size_t i = 0; i < t.state.positions.size(); ++i) sum += t.settings.rest_positions[i].z() - t.state.positions[i].z();
  return sum / static_cast<Real>(t.state.positions.size());
}

TEST(HomeYield, ASteadyLoadWithinTheYieldSagsElasticallyAndBeyondItCreeps) {
  // Each keeps the anchors its own way: read live (XPBD), copied into padded passes (semi-implicit
  // Euler) or into the AVX2 solve (implicit Euler), both re-copied when they yield.
  for (const IntegratorKind kind :
       {IntegratorKind::kSemiImplicitEuler, IntegratorKind::kImplicitEuler, IntegratorKind::kXpbd}) {
    // The sheet's vertices differ in mass (lumped by area): the mean m_i g / k_home is 2 mm.
    const Real elastic = sag(kind, 0, 2.0);
    const Real within = sag(kind, 0.005, 2.0);
    const Real beyond_1s = sag(kind, 0.001, 1.0), beyond_2s = sag(kind, 0.001, 2.0);
    std::printf("%s: sag elastic %.3f mm, yield 5 mm %.3f mm, yield 1 mm %.3f mm at 1 s and %.3f mm at 2 s\n",
                integrator_name(kind), 1e3 * elastic, 1e3 * within, 1e3 * beyond_1s,
                1e3 * beyond_2s);
    EXPECT_NEAR(elastic, 0.002, 0.0001);
    EXPECT_NEAR(within, elastic, 1e-9);  // never yielded: the same steps, the same sag
    // Beyond: the anchors give, the sheet keeps falling (measured 0.2 m/s; (m g − k_home·yield) / (γ m)
    // = 0.25 m/s with the anchors current, and they lag a step).
    EXPECT_GT(beyond_1s, 0.1);
    EXPECT_GT(beyond_2s, beyond_1s + 0.15);
  }
}

}  // namespace
}  // namespace trocar
