// The thermal damage model against its closed forms (docs/electrosurgery.md).
#include "trocar/electrosurgery/thermal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace trocar {
namespace {

// One right triangle of legs 2 mm: A = 2e-6 m².
struct OneTriangle {
  std::vector<Vec3> positions{Vec3(0, 0, 0), Vec3(2e-3, 0, 0), Vec3(0, 2e-3, 0)};
  std::vector<Triangle> triangles{{0, 1, 2}};
  std::vector<Real> areas{2e-6};
};

ThermalProperties no_perfusion() {
  ThermalProperties p;
  p.perfusion = 0;
  return p;
}

TEST(ThermalDamage, RateIsArrheniusAtHandComputedTemperatures) {
  const ThermalProperties p;
  // A exp(−E_a/(R T)) with A = 3.1e98 /s, E_a = 6.28e5 J/mol (Henriques & Moritz 1947).
  EXPECT_NEAR(damage_rate(p, 333.15), 1.0692201209, 1e-8);   // 60 °C: Ω = 1 in about a second
  EXPECT_NEAR(damage_rate(p, 343.15) / 791.46758183, 1.0, 1e-9);  // 70 °C
  EXPECT_LT(damage_rate(p, 310.15), 1e-7);                     // 37 °C: nothing in a session
}

TEST(ThermalDamage, ConstantPowerHeatsLinearlyThenBoilsTheWaterOff) {
  const OneTriangle m;
  const ThermalProperties p = no_perfusion();
  ThermalField field(p, m.triangles, m.positions, m.areas);
  const Real mass = p.density * 2e-6 * p.heated_depth;        // 1.05e-6 kg (0.5 mm deep)
  const Real capacity = mass * p.specific_heat;                // 3.78e-3 J/K
  const Real power = 5.0;                                      // W
  const Real boil_at = capacity * (p.boiling_temperature - p.body_temperature) / power;  // 0.0476 s
  const Real vaporise_in = mass * p.water_fraction * p.latent_heat / power;             // 0.332 s
  const std::vector<Real> watts{power};
  const Real dt = 1e-3;
  for (int step = 1; step <= 900; ++step) {
    field.step(watts, dt);
    const Real t = step * dt;
    if (t < boil_at) {
      EXPECT_NEAR(field.temperature()[0], p.body_temperature + power * t / capacity, 1e-9) << t;
      EXPECT_EQ(field.vaporised()[0], 0.0);
    } else {
      EXPECT_DOUBLE_EQ(field.temperature()[0], p.boiling_temperature) << t;
      EXPECT_NEAR(field.vaporised()[0], (t - boil_at) / vaporise_in, 1e-9) << t;
    }
  }
  EXPECT_TRUE(field.cut(0));  // 0.9 s > 0.0476 + 0.332 s
  EXPECT_TRUE(field.coagulated(0));
}

TEST(ThermalDamage, DamageOfALinearRampMatchesAFineQuadrature) {
  const OneTriangle m;
  const ThermalProperties p = no_perfusion();
  ThermalField field(p, m.triangles, m.positions, m.areas);
  const Real capacity = p.density * 2e-6 * p.heated_depth * p.specific_heat;
  const Real power = 0.15;  // W: 39.7 K/s, reaches 68.9 °C at 0.8 s
  const std::vector<Real> watts{power};
  for (int step = 0; step < 800; ++step) field.step(watts, 1e-3);
  // Independent: the midpoint rule on 10⁶ intervals of the closed-form T(t) = T_b + P t / C.
  const int n = 1000000;
  Real expected = 0;
  for (int k = 0; k < n; ++k) {
    const Real t = (k + 0.5) * 0.8 / n;
    expected += damage_rate(p, p.body_temperature + power * t / capacity) * 0.8 / n;
  }
  EXPECT_GT(expected, 1.0);  // coagulated by the end of the ramp
  EXPECT_NEAR(field.damage()[0] / expected, 1.0, 1e-4);
}

TEST(ThermalDamage, AtTheBoilingPointDamageGrowsAtTheConstantRate) {
  const OneTriangle m;
  const ThermalProperties p = no_perfusion();
  ThermalField field(p, m.triangles, m.positions, m.areas);
  const std::vector<Real> watts{5.0};
  for (int step = 0; step < 100; ++step) field.step(watts, 1e-3);  // boiling from 0.0476 s
  const Real before = field.damage()[0];
  for (int step = 0; step < 100; ++step) field.step(watts, 1e-3);
  EXPECT_NEAR((field.damage()[0] - before) / (0.1 * damage_rate(p, p.boiling_temperature)), 1.0, 1e-9);
}

TEST(ThermalDamage, PerfusionCoolsToTheSteadyStateOfPennes) {
  const OneTriangle m;
  ThermalProperties p;
  p.perfusion = p.density * p.specific_heat / p.blood_specific_heat;  // β = 1 /s
  ThermalField field(p, m.triangles, m.positions, m.areas);
  const Real capacity = p.density * 2e-6 * p.heated_depth * p.specific_heat;
  const Real power = 0.1;  // steady rise P / (C β) = 26.5 K, below boiling
  const std::vector<Real> watts{power};
  const Real dt = 1e-4;
  for (int step = 1; step <= 30000; ++step) {
    field.step(watts, dt);
    if (step % 5000 == 0) {
      const Real t = step * dt;
      // Explicit Euler of dT/dt = P/C − β (T − T_b): relative error about β dt / 2 = 5e-5.
      const Real expected = power / capacity * (1 - std::exp(-t));
      EXPECT_NEAR((field.temperature()[0] - p.body_temperature) / expected, 1.0, 1e-4) << t;
    }
  }
}

// A 6 × 6 grid of 2 mm squares, each split in two: 72 triangles, conduction across 2·6·5 + 36 edges.
struct Grid {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  std::vector<Real> areas;
  Grid() {
    const int n = 6;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) positions.emplace_back(2e-3 * i, 2e-3 * j, 0);
    auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    areas.assign(triangles.size(), 2e-6);
  }
};

TEST(ThermalDamage, EnergyIsConservedAcrossHeatingConductionBoilingAndPerfusion) {
  const Grid g;
  ThermalProperties p;
  p.perfusion = 50;  // enough to carry off a measurable share
  ThermalField field(p, g.triangles, g.positions, g.areas);
  std::vector<Real> watts(g.triangles.size(), 0.0);
  watts[30] = 8.0;  // an electrode on one triangle near the middle: it boils
  for (int step = 0; step < 400; ++step) field.step(watts, 1e-3);
  watts[30] = 0;
  for (int step = 0; step < 400; ++step) field.step(watts, 1e-3);
  EXPECT_NEAR(field.delivered(), 8.0 * 0.4, 1e-12);
  EXPECT_GT(field.latent(), 0.1 * field.delivered());
  EXPECT_GT(field.perfused(), 0.0);
  EXPECT_NEAR((field.stored() + field.latent() + field.perfused()) / field.delivered(), 1.0, 1e-12);
  // Heat spread: the neighbours warmed, the far corner barely.
  EXPECT_GT(field.temperature()[31], p.body_temperature + 5.0);
  EXPECT_LT(field.temperature()[0], field.temperature()[31]);
}

TEST(ThermalDamage, TwoTrianglesConductAtTheHandComputedConductance) {
  // A 2 mm square split along its diagonal: ℓ = 2√2 mm, centroids (4/3, 2/3) and (2/3, 4/3) mm
  // apart by s = √8/3 mm, G = κ d ℓ / s = 0.5 W/(m·K) · 5e-4 m · 3 = 7.5e-4 W/K.
  const std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(2e-3, 0, 0), Vec3(2e-3, 2e-3, 0), Vec3(0, 2e-3, 0)};
  const std::vector<Triangle> tris{{0, 1, 2}, {0, 2, 3}};
  const std::vector<Real> areas{2e-6, 2e-6};
  ThermalField field(no_perfusion(), tris, x, areas);
  const std::vector<Real> watts{1.0, 0.0};
  for (int step = 0; step < 20; ++step) field.step(watts, 1e-3);  // 0.02 J into the first
  const Real capacity = 1050 * 2e-6 * 5e-4 * 3600;
  const Real mean = 310.15 + 0.02 / (2 * capacity);
  const Real gap0 = field.temperature()[0] - field.temperature()[1];
  const std::vector<Real> none;
  const int steps = 5000;
  for (int step = 0; step < steps; ++step) field.step(none, 1e-3);
  // The gap decays as (1 − 2 G h / C)^n (explicit Euler of dΔ/dt = −2 G Δ / C; τ = C / 2G = 2.5 s).
  const Real conductance = 7.5e-4;
  const Real gap = field.temperature()[0] - field.temperature()[1];
  EXPECT_NEAR(gap / (gap0 * std::pow(1 - 2 * conductance * 1e-3 / capacity, steps)), 1.0, 1e-9);
  EXPECT_NEAR(0.5 * (field.temperature()[0] + field.temperature()[1]), mean, 1e-9);
}

TEST(ThermalDamage, RemapKeepsTheStateOfTheRemainingTriangles) {
  const Grid g;
  ThermalField field(no_perfusion(), g.triangles, g.positions, g.areas);
  std::vector<Real> watts(g.triangles.size(), 0.0);
  watts[5] = 3.0;
  for (int step = 0; step < 50; ++step) field.step(watts, 1e-3);
  std::vector<std::uint32_t> origin;
  std::vector<Triangle> kept;
  for (std::uint32_t t = 0; t < g.triangles.size(); ++t)
    if (t != 4) {
      origin.push_back(t);
      kept.push_back(g.triangles[t]);
    }
  const Real t5 = field.temperature()[5], d5 = field.damage()[5];
  const std::vector<Real> areas(kept.size(), 2e-6);
  field.remap(origin, kept, g.positions, areas);
  ASSERT_EQ(field.size(), 71u);
  EXPECT_EQ(field.temperature()[4], t5);  // old 5 is new 4
  EXPECT_EQ(field.damage()[4], d5);
  EXPECT_TRUE(field.hot());
}

TEST(ThermalDamage, ACutsRemapConductsExactlyAsAFieldBuiltOnTheCutSurface) {
  // The remap keeps the old links between kept triangles; a field built from scratch on the cut
  // surface (the same state set by heating to it) must then step to the same bits.
  const Grid g;
  ThermalField field(no_perfusion(), g.triangles, g.positions, g.areas);
  std::vector<Real> watts(g.triangles.size(), 0.0);
  watts[20] = 3.0;
  watts[41] = 2.0;
  for (int step = 0; step < 40; ++step) field.step(watts, 1e-3);
  std::vector<std::uint32_t> origin;
  std::vector<Triangle> kept;
  for (std::uint32_t t = 0; t < g.triangles.size(); ++t)
    if (t != 21 && t != 22 && t != 40) {
      origin.push_back(t);
      kept.push_back(g.triangles[t]);
    }
  const std::vector<Real> areas(kept.size(), 2e-6);
  field.remap(origin, kept, g.positions, areas);
  // The reference: built on the cut surface, given the same temperatures through add_heat.
  ThermalField fresh(no_perfusion(), kept, g.positions, areas);
  const ThermalProperties p = no_perfusion();
  const Real capacity = p.density * 2e-6 * p.heated_depth * p.specific_heat;  // J/K per triangle
  for (std::uint32_t k = 0; k < kept.size(); ++k)
    fresh.add_heat(k, (field.temperature()[k] - fresh.temperature()[k]) * capacity);
  ASSERT_LT(field.temperature()[19], p.boiling_temperature);  // below boiling: add_heat sets it exactly
  std::vector<Real> now(kept.size(), 0.0);
  now[19] = 3.0;
  for (int step = 0; step < 40; ++step) {
    field.step(now, 1e-3);
    fresh.step(now, 1e-3);
  }
  for (std::uint32_t k = 0; k < kept.size(); ++k)
    EXPECT_NEAR(field.temperature()[k] - fresh.temperature()[k], 0.0, 1e-9) << k;
}

}  // namespace
}  // namespace trocar
