// Bleeding through the simulation's step (docs/electrosurgery.md, "Bleeding"): a vessel cut open
// bleeds at v̄ πd²/4, coagulating the bleeding point seals a small one, a wide one needs a clip, and
// a small vessel cut through by the live hook does not bleed (it is coagulated as it is cut).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/inguinal_anatomy.h"
#include "trocar/mesh/instruments.h"
#include "trocar/sim/simulation.h"
#include "support/vessel.h"

namespace trocar {
namespace {

/// A 3 cm vessel (a tube of radius 2 mm along x, its ends held) whose lumen is `diameter`.
Simulation vessel(Real diameter, bool artery, Real hook_power = 0) {
  World world;
  test::add_held_vessel(world, "vessel", Vec3::Zero(), 0.015, 0.002, 12, 0.014, VesselSpec{diameter, artery});
  if (hook_power > 0) {
    // The hook's foot across the vessel's top, pressed 0.2 mm in.
    const Quat q(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitZ()));
    InstrumentBody& hook = world.add_instrument("hook", Instrument(make_hook_probe().mesh, Vec3::UnitZ()),
                                                KeyframeMotion({{0, Vec3(0, -0.0025, 0.0018), q, 0}}));
    hook.electrode.power = hook_power;
  }
  return Simulation(std::move(world), SimulationSettings{});
}

/// The triangle of the vessel whose centroid is nearest the top of its middle.
std::uint32_t top_triangle(const Simulation& sim) {
  const MassSpringSettings& s = sim.world().tissues[0]->settings;
  std::uint32_t best = 0;
  Real d = 1e9;
  for (std::uint32_t k = 0; k < s.triangles.size(); ++k) {
    const Vec3 c = (s.rest_positions[s.triangles[k][0]] + s.rest_positions[s.triangles[k][1]] +
                    s.rest_positions[s.triangles[k][2]]) / 3;
    if ((c - Vec3(0, 0, 0.002)).norm() < d) {
      d = (c - Vec3(0, 0, 0.002)).norm();
      best = k;
    }
  }
  return best;
}

/// Heats the triangles around wound 0's vertex by 70 K, to the boiling point and a little beyond
/// (the hook on the bleeding point; not enough to boil a triangle's water off).
void coagulate_wound(Simulation& sim) {
  const auto& wound = sim.bleeding().wounds()[0];
  const TissueBody& tissue = *sim.world().tissues[0];
  const ThermalProperties& p = tissue.thermal;
  for (std::uint32_t k = 0; k < tissue.settings.triangles.size(); ++k)
    for (std::uint32_t v : tissue.settings.triangles[k])
      if (v == wound.vertex)
        sim.heat(0, k, 70 * p.density * p.specific_heat * p.heated_depth * tissue.settings.rest_areas[k]);
}

TEST(BleedingSim, ASmallVesselCutBleedsItsRateAndCoagulationSealsIt) {
  Simulation sim = vessel(0.0015, true);
  for (int n = 0; n < 20; ++n) sim.step(1e-3);
  const std::uint32_t cut[] = {top_triangle(sim)};
  sim.cut(0, cut);  // scissors: no heat, so nothing sealed it
  ASSERT_EQ(sim.bleeding().wounds().size(), 1u);
  for (int n = 0; n < 500; ++n) ASSERT_TRUE(sim.step(1e-3).finite);
  // Q = v̄ π d² / 4 = 0.15 m/s · π · (0.75 mm)² = 2.651e-7 m³/s: 0.1325 ml in 0.5 s.
  const Real q = 0.15 * std::numbers::pi * 0.0015 * 0.0015 / 4;
  EXPECT_NEAR(sim.bleeding().emitted() / (q * 0.5), 1.0, 1e-9);
  EXPECT_EQ(sim.bleeding().state(0), WoundState::kBleeding);
  coagulate_wound(sim);
  for (int n = 0; n < 10; ++n) sim.step(1e-3);
  ASSERT_EQ(sim.bleeding().state(0), WoundState::kSealed);  // Ω far above 2.25 within a step at 100 °C
  const Real bled = sim.bleeding().emitted();
  EXPECT_LT(bled, q * 0.502);
  for (int n = 0; n < 200; ++n) sim.step(1e-3);
  EXPECT_EQ(sim.bleeding().emitted(), bled);  // stopped
  ASSERT_TRUE(sim.bleeding().time_to_haemostasis(0).has_value());
  EXPECT_NEAR(*sim.bleeding().time_to_haemostasis(0), 0.5, 0.002);
}

TEST(BleedingSim, AWideVesselNeedsAClip) {
  Simulation sim = vessel(0.004, false);
  for (int n = 0; n < 20; ++n) sim.step(1e-3);
  const std::uint32_t cut[] = {top_triangle(sim)};
  sim.cut(0, cut);
  for (int n = 0; n < 100; ++n) sim.step(1e-3);
  coagulate_wound(sim);
  for (int n = 0; n < 100; ++n) sim.step(1e-3);
  EXPECT_EQ(sim.bleeding().state(0), WoundState::kNeedsClip);  // 4 mm: beyond the hook's 2 mm
  // A 4 mm vein: 0.03 m/s · π · (2 mm)² = 3.770e-7 m³/s for the 0.2 s it has bled.
  const Real q = 0.03 * std::numbers::pi * 0.004 * 0.004 / 4;
  EXPECT_NEAR(sim.bleeding().emitted() / (q * 0.2), 1.0, 1e-9);
  sim.clip(0);
  const Real bled = sim.bleeding().emitted();
  for (int n = 0; n < 100; ++n) sim.step(1e-3);
  EXPECT_EQ(sim.bleeding().state(0), WoundState::kClipped);
  EXPECT_EQ(sim.bleeding().emitted(), bled);
}

TEST(BleedingSim, TheLiveHookCutsASmallVesselWithoutBleedingAndAWideOneOpen) {
  for (const Real diameter : {0.0015, 0.004}) {
    Simulation sim = vessel(diameter, true, 40);
    sim.set_energy(0, true);
    std::uint32_t cut = 0;
    for (int n = 0; n < 1500 && cut == 0; ++n) {
      ASSERT_TRUE(sim.step(1e-3).finite);
      cut = sim.burn_tally(0).cut_triangles;
    }
    ASSERT_GT(cut, 0u) << diameter;
    for (int n = 0; n < 50; ++n) sim.step(1e-3);
    if (diameter < 0.002) {
      EXPECT_EQ(sim.bleeding().wounds().size(), 0u) << "coagulated as it was cut: sealed";
    } else {
      ASSERT_EQ(sim.bleeding().wounds().size(), 1u);
      EXPECT_GT(sim.bleeding().emitted(), 0.0);
      EXPECT_EQ(sim.bleeding().state(0), WoundState::kNeedsClip);  // the hook stayed on it
    }
  }
}

}  // namespace
}  // namespace trocar
