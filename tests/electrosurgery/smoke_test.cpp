// Surgical smoke against hand-computed counts, closed forms and its invariants
// (docs/electrosurgery.md, "Smoke"; src/trocar/electrosurgery/smoke.h).
#include "trocar/electrosurgery/smoke.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace trocar {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

// Still smoke: born exactly where emitted, at rest, no lift, drag, spread, growth or fade. Each
// test turns on the one process it checks.
SmokeSettings still() {
  SmokeSettings s;
  s.rise_speed = 0;
  s.buoyancy_time = 0;
  s.drag_time = kInf;
  s.diffusion = 0;
  s.position_jitter = 0;
  s.velocity_jitter = 0;
  s.growth_rate = 0;
  s.fade_half_life = kInf;
  return s;
}

Real total_opacity(const SmokeField& field) {
  Real sum = 0;
  for (const SmokeParticle& p : field.particles()) sum += p.opacity;
  return sum;
}

// ---- Emission --------------------------------------------------------------------------------

TEST(SmokeEmission, CountIsEnergyTimesRateRounded) {
  SmokeSettings s = still();
  s.particles_per_joule = 100;
  {
    SmokeField field(s, 1);
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.123);  // 12.3 → 12
    EXPECT_EQ(field.size(), 12u);
    EXPECT_EQ(field.emitted(), 12u);
  }
  {
    SmokeField field(s, 1);
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.125);  // 12.5 (exact in binary) → 13
    EXPECT_EQ(field.size(), 13u);
  }
  {
    SmokeField field(s, 1);
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.004);  // 0.4 → 0
    EXPECT_EQ(field.size(), 0u);
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.0);    // nothing, and no carry change
    field.emit(Vec3::Zero(), Vec3::UnitZ(), -1.0);
    field.emit(Vec3::Zero(), Vec3::UnitZ(), std::numeric_limits<Real>::quiet_NaN());
    EXPECT_EQ(field.emitted(), 0u);
    // Carried: 0.4 + 0.4 = 0.8 → one particle in all (round(0.8) = 1), at the second call.
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.004);
    EXPECT_EQ(field.emitted(), 1u);
  }
}

TEST(SmokeEmission, ManySmallEmissionsGiveTheCountOfOneBig) {
  for (const Real rate : {100.0, 37.3, 413.0}) {
    SmokeSettings s = still();
    s.particles_per_joule = rate;
    s.capacity = 1000;
    SmokeField many(s, 7), one(s, 7);
    for (int k = 0; k < 1000; ++k) many.emit(Vec3::Zero(), Vec3::UnitZ(), 1e-3);
    one.emit(Vec3::Zero(), Vec3::UnitZ(), 1.0);
    EXPECT_EQ(one.emitted(), static_cast<std::size_t>(std::lround(rate))) << rate;
    const auto a = static_cast<long>(many.emitted()), b = static_cast<long>(one.emitted());
    EXPECT_LE(std::abs(a - b), 1) << rate;
  }
  // Each call alone rounds to nothing (0.1 particle), their sum does not.
  SmokeSettings s = still();
  SmokeField field(s, 7);
  for (int k = 0; k < 1000; ++k) field.emit(Vec3::Zero(), Vec3::UnitZ(), 1e-3);
  EXPECT_EQ(field.emitted(), 100u);
}

TEST(SmokeEmission, BirthStateIsTheSettings) {
  SmokeSettings s;  // the defaults, jitter off so the birth state is exact
  s.position_jitter = 0;
  s.velocity_jitter = 0;
  SmokeField field(s, 3);
  const Vec3 at(0.01, -0.02, 0.03), up(0, 0.6, 0.8);
  field.emit(at, 2.0 * up, 0.05);  // `up` not unit: normalised
  ASSERT_EQ(field.size(), 5u);
  for (const SmokeParticle& p : field.particles()) {
    EXPECT_EQ(p.position, at);
    EXPECT_NEAR((p.velocity - 0.05 * up).norm(), 0, 1e-17);          // rise_speed along up
    EXPECT_NEAR((p.lift - (0.05 / 0.5) * up).norm(), 0, 1e-16);       // rise_speed / drag_time
    EXPECT_EQ(p.age, 0.0);
    EXPECT_EQ(p.radius, 3e-3);
    EXPECT_EQ(p.opacity, 0.08);
  }
}

TEST(SmokeEmission, JitterHasTheStatedSpread) {
  SmokeSettings s = still();
  s.position_jitter = 1e-3;
  s.velocity_jitter = 0.01;
  s.capacity = 5000;
  SmokeField field(s, 11);
  field.emit(Vec3(1, 2, 3), Vec3::UnitZ(), 50.0);
  ASSERT_EQ(field.size(), 5000u);
  Real px = 0, pxx = 0, vxx = 0;
  for (const SmokeParticle& p : field.particles()) {
    for (int a = 0; a < 3; ++a) {
      const Real dx = p.position[a] - Real(a + 1);
      px += dx;
      pxx += dx * dx;
      vxx += p.velocity[a] * p.velocity[a];
    }
  }
  const Real n = 15000;
  EXPECT_NEAR(px / n, 0, 4 * 1e-3 / std::sqrt(n));
  // Sample variance within ±4 % (4 standard errors of √(2/n) ≈ 1.2 %).
  EXPECT_NEAR(pxx / n / 1e-6, 1.0, 0.04);
  EXPECT_NEAR(vxx / n / 1e-4, 1.0, 0.04);
}

// ---- Capacity --------------------------------------------------------------------------------

TEST(SmokeCapacity, NeverExceededAndNeverReallocated) {
  SmokeSettings s;  // the defaults: rise, spread, growth, fade
  s.capacity = 256;
  SmokeField field(s, 5);
  EXPECT_EQ(field.capacity(), 256u);
  field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.01);
  const SmokeParticle* storage = field.particles().data();
  std::size_t most = 0;
  for (int k = 0; k < 300; ++k) {
    field.emit(Vec3(1e-4 * k, 0, 0), Vec3::UnitZ(), 0.5);  // 50 a call: full after 6 calls
    ASSERT_LE(field.size(), 256u) << k;
    field.step(0.01);
    if (k % 7 == 0) field.suction(Vec3(1e-4 * k, 0, 0.01), 0.005, 0.01);
    if (k == 150) field.set_venting(true);
    ASSERT_LE(field.size(), 256u) << k;
    EXPECT_EQ(field.particles().data(), storage) << k;  // the pool never moved
    most = std::max(most, field.size());
  }
  EXPECT_EQ(most, 256u);
  EXPECT_EQ(field.capacity(), 256u);
  EXPECT_EQ(field.emitted(), 1u + 300u * 50u);
  // More than the pool in one call: the last `capacity` of them, all newborn.
  field.emit(Vec3::Zero(), Vec3::UnitZ(), 10.0);
  EXPECT_EQ(field.size(), 256u);
  for (const SmokeParticle& p : field.particles()) EXPECT_EQ(p.age, 0.0);
}

TEST(SmokeCapacity, WhenFullTheOldestMakeRoom) {
  SmokeSettings s = still();
  s.capacity = 10;
  s.fade_half_life = 5;  // in still air the oldest are the faintest
  SmokeField field(s, 5);
  for (int k = 0; k < 5; ++k) field.emit(Vec3(k, 0, 0), Vec3::UnitZ(), 0.01);  // 0 … 4 at x = k
  field.step(1.0);
  for (int k = 5; k < 10; ++k) field.emit(Vec3(k, 0, 0), Vec3::UnitZ(), 0.01);
  field.step(0.5);
  ASSERT_EQ(field.size(), 10u);
  field.emit(Vec3(10, 0, 0), Vec3::UnitZ(), 0.03);  // 3 more: particles 0, 1, 2 make room
  ASSERT_EQ(field.size(), 10u);
  const std::vector<Real> x{10, 10, 10, 3, 4, 5, 6, 7, 8, 9};  // replaced in their slots
  const std::vector<Real> age{0, 0, 0, 1.5, 1.5, 0.5, 0.5, 0.5, 0.5, 0.5};
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_EQ(field.particles()[i].position.x(), x[i]) << i;
    EXPECT_EQ(field.particles()[i].age, age[i]) << i;
  }
  // The next oldest, 3 and 4, go next; and then, all of that batch being equally faint, the
  // lowest slots of the second batch.
  field.emit(Vec3(11, 0, 0), Vec3::UnitZ(), 0.03);
  const std::vector<Real> x2{10, 10, 10, 11, 11, 11, 6, 7, 8, 9};
  for (std::size_t i = 0; i < 10; ++i) EXPECT_EQ(field.particles()[i].position.x(), x2[i]) << i;
}

TEST(SmokeCapacity, WhenFullTheFaintestMakeRoomFirst) {
  SmokeSettings s = still();
  s.capacity = 4;
  s.fade_half_life = 5;
  SmokeField field(s, 5);
  for (int k = 0; k < 4; ++k) field.emit(Vec3(k, 0, 0), Vec3::UnitZ(), 0.01);
  field.step(1.0);
  field.suction(Vec3(2, 0, 0), 0.1, 0.05);  // particle 2 alone, e^{−0.5}: now the faintest
  field.emit(Vec3(9, 0, 0), Vec3::UnitZ(), 0.01);
  const std::vector<Real> x{0, 1, 9, 3};
  ASSERT_EQ(field.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(field.particles()[i].position.x(), x[i]) << i;
}

// ---- Spread ----------------------------------------------------------------------------------

TEST(SmokeSpread, VarianceGrowsAsTwoDt) {
  SmokeSettings s = still();
  s.diffusion = 5e-5;
  s.capacity = 6000;
  SmokeField field(s, 2024);
  const Vec3 at(0.1, 0.2, 0.3);
  field.emit(at, Vec3::UnitZ(), 60.0);
  ASSERT_EQ(field.size(), 6000u);
  Real t = 0;
  for (const Real until : {0.5, 2.0}) {
    while (t < until - 1e-9) {
      field.step(0.01);
      t += 0.01;
    }
    Real mean = 0, var = 0;
    for (const SmokeParticle& p : field.particles())
      for (int a = 0; a < 3; ++a) {
        const Real d = p.position[a] - at[a];
        mean += d;
        var += d * d;
      }
    const Real n = 18000;
    const Real expected = 2 * s.diffusion * until;  // 5e-5 m² at 0.5 s, 2e-4 m² at 2 s
    // The sample variance's standard error is √(2/n) ≈ 1.1 %: ±4 % is 3.8 of them.
    EXPECT_NEAR(var / n / expected, 1.0, 0.04) << until;
    EXPECT_NEAR(mean / n, 0, 4 * std::sqrt(expected / n)) << until;
  }
  EXPECT_EQ(field.size(), 6000u);
}

// ---- Rise ------------------------------------------------------------------------------------

// Mean height along `up` of a still-air plume against the closed form of
// x'' = a e^{−t/τ_b} − x'/τ_d with x'(0) = w, a = w/τ_d.
Real closed_form_height(Real w, Real tau_d, Real tau_b, Real t) {
  const Real a = w / tau_d;
  const Real coast = w * tau_d * (1 - std::exp(-t / tau_d));
  if (tau_d == tau_b) return coast + a * tau_d * tau_d * (1 - std::exp(-t / tau_d) * (1 + t / tau_d));
  const Real k = 1 / tau_d - 1 / tau_b;
  return coast + a * (tau_b * (1 - std::exp(-t / tau_b)) - tau_d * (1 - std::exp(-t / tau_d))) / k;
}

TEST(SmokeRise, MeanHeightFollowsTheBuoyantClosedForm) {
  for (const Real tau_b : {0.5, 1.0}) {
    SmokeSettings s;  // rise 5 cm/s, τ_d = 0.5 s, jitter and spread off so every puff is the mean
    s.buoyancy_time = tau_b;
    s.fade_half_life = kInf;  // so that it lives as long as the test looks
    s.diffusion = 0;
    s.position_jitter = 0;
    s.velocity_jitter = 0;
    SmokeField field(s, 9);
    const Vec3 at(0.02, 0.01, -0.03), up = Vec3(1, 2, 2) / 3;
    field.emit(at, up, 0.01);  // one puff
    Real last = 0;
    for (int k = 1; k <= 3000; ++k) {
      field.step(1e-3);
      const Real height = (field.particles()[0].position - at).dot(up);
      EXPECT_GT(height, last) << k;  // it rises all the time (slower and slower)
      last = height;
      if (k % 500 == 0) {
        const Real t = k * 1e-3;
        EXPECT_NEAR(height, closed_form_height(0.05, 0.5, tau_b, t), 1e-13) << tau_b << " " << t;
      }
    }
    // In all it rises w (τ_d + τ_b): 5 cm (τ_b = 0.5 s), 7.5 cm (1 s).
    for (int k = 0; k < 20000; ++k) field.step(1e-3);  // 23 s
    ASSERT_EQ(field.size(), 1u);
    const Real height = (field.particles()[0].position - at).dot(up);
    EXPECT_NEAR(height, closed_form_height(0.05, 0.5, tau_b, 23.0), 1e-13) << tau_b;
    EXPECT_NEAR(height, 0.05 * (0.5 + tau_b), 1e-10) << tau_b;  // less w τ_b e^{−23/τ_b}/… ≈ 1e-11
    // The same at the frame rate: the step's integrals are exact, not first order.
    SmokeField frames(s, 9);
    frames.emit(at, up, 0.01);
    for (int k = 0; k < 60; ++k) frames.step(1.0 / 60);
    EXPECT_NEAR((frames.particles()[0].position - at).dot(up), closed_form_height(0.05, 0.5, tau_b, 1.0), 1e-13);
  }
}

TEST(SmokeRise, PlumeMeanHeightGrowsWithJitterAndSpread) {
  SmokeField field(SmokeSettings{}, 4);  // the defaults
  for (int k = 0; k < 100; ++k) field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.03);  // 100 ms of 30 W
  Real last = -1;
  for (int frame = 0; frame < 60; ++frame) {
    field.step(1.0 / 60);
    Real mean = 0;
    for (const SmokeParticle& p : field.particles()) mean += p.position.z();
    mean /= static_cast<Real>(field.size());
    EXPECT_GT(mean, last) << frame;
    last = mean;
  }
  EXPECT_GT(last, 0.02);  // at 1 s: 3.6 cm by the closed form, less the spread's noise
  EXPECT_LT(last, 0.05);
}

TEST(SmokeRise, WithoutBuoyancyDragDecaysTheVelocityExponentially) {
  SmokeSettings s = still();
  s.rise_speed = 0.05;
  s.drag_time = 0.4;
  SmokeField field(s, 9);
  field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.01);
  const Real dt = 1.0 / 60;  // a frame: the decay is exact at any step
  for (int k = 1; k <= 120; ++k) {
    field.step(dt);
    const Real t = k * dt;
    const SmokeParticle& p = field.particles()[0];
    EXPECT_NEAR(p.velocity.z() / (0.05 * std::exp(-t / 0.4)), 1.0, 1e-12) << t;
    EXPECT_EQ(p.velocity.x(), 0.0);
    // It coasts w τ (1 − e^{−t/τ}), exactly (the position takes the step's exact ∫ v).
    EXPECT_NEAR(p.position.z(), 0.05 * 0.4 * (1 - std::exp(-t / 0.4)), 1e-15) << t;
  }
}

// ---- Fade ------------------------------------------------------------------------------------

TEST(SmokeFade, TotalOpacityHalvesInTheHalfLife) {
  SmokeSettings s;  // defaults: t½ = 5 s, with rise and spread, growth off
  s.growth_rate = 0;
  SmokeField field(s, 8);
  field.emit(Vec3::Zero(), Vec3::UnitZ(), 1.0);
  ASSERT_EQ(field.size(), 100u);
  const Real start = total_opacity(field);
  EXPECT_NEAR(start, 100 * 0.08, 1e-12);
  for (int k = 0; k < 500; ++k) field.step(0.01);
  EXPECT_NEAR(total_opacity(field) / start, 0.5, 1e-12);
  for (int k = 0; k < 500; ++k) field.step(0.01);
  EXPECT_NEAR(total_opacity(field) / start, 0.25, 1e-12);
  EXPECT_EQ(field.size(), 100u);
}

TEST(SmokeFade, GrowthDilutesButKeepsTheCover) {
  SmokeSettings s;  // defaults: r₀ = 3 mm growing 3 mm/s up to 12 mm, t½ = 5 s
  SmokeField field(s, 8);
  field.emit(Vec3::Zero(), Vec3::UnitZ(), 1.0);
  const Real start = field.total_cover();
  EXPECT_NEAR(start, 100 * 0.08 * 9e-6, 1e-15);
  for (int k = 0; k < 100; ++k) field.step(0.01);
  // 1 s: r = 6 mm, α = 0.08 · (3/6)² · 2^{−1/5}
  EXPECT_NEAR(field.particles()[0].radius, 6e-3, 1e-15);
  EXPECT_NEAR(field.particles()[0].opacity, 0.02 * std::pow(2.0, -0.2), 1e-14);
  for (int k = 0; k < 400; ++k) field.step(0.01);
  // 5 s: r = 12 mm (the cap), α = 0.08 / 16 / 2 = 0.0025, the cover halved
  EXPECT_NEAR(field.particles()[0].radius, 0.012, 1e-15);
  EXPECT_NEAR(field.particles()[0].opacity, 0.0025, 1e-14);
  EXPECT_NEAR(field.total_cover() / start, 0.5, 1e-12);
  // It goes below min_opacity 1e-3 at 5 + 5 log2(2.5) = 11.6 s.
  for (int k = 0; k < 650; ++k) field.step(0.01);  // 11.5 s
  EXPECT_EQ(field.size(), 100u);
  for (int k = 0; k < 20; ++k) field.step(0.01);  // 11.7 s
  EXPECT_EQ(field.size(), 0u);
}

TEST(SmokeFade, VentingClearsAtTheCombinedRate) {
  SmokeSettings s;  // t½ = 5 s, τ_v = 2 s
  s.growth_rate = 0;
  SmokeField field(s, 8);
  field.emit(Vec3::Zero(), Vec3::UnitZ(), 1.0);
  const Real start = total_opacity(field);
  for (int k = 0; k < 100; ++k) field.step(0.01);  // 1 s still
  field.set_venting(true);
  EXPECT_TRUE(field.venting());
  for (int k = 0; k < 200; ++k) field.step(0.01);  // 2 s venting
  // 2^{−3/5} e^{−2/2} = 0.659754 · 0.367879 = 0.242710
  const Real expected = std::pow(2.0, -3.0 / 5.0) * std::exp(-1.0);
  EXPECT_NEAR(total_opacity(field) / start, expected, 1e-12);
  EXPECT_NEAR(expected, 0.242710, 1e-6);
  field.set_venting(false);
  for (int k = 0; k < 100; ++k) field.step(0.01);
  EXPECT_NEAR(total_opacity(field) / start, expected * std::pow(2.0, -0.2), 1e-12);
}

// ---- Suction ---------------------------------------------------------------------------------

TEST(SmokeSuction, ClearsWithinItsRadiusAtTheStatedRateAndNothingOutside) {
  SmokeSettings s = still();  // τ_s = 0.1 s, α₀ = 0.08, min_opacity 1e-3
  SmokeField field(s, 8);
  const Vec3 tip(0.01, 0.02, 0.03);
  const std::vector<Real> distance{0.005, 0.0199, 0.012, 0.0201, 0.04};  // radius 2 cm: 3 inside
  const Vec3 dir = Vec3(2, -1, 2) / 3;
  for (const Real d : distance) field.emit(tip + d * dir, Vec3::UnitZ(), 0.01);
  ASSERT_EQ(field.size(), 5u);
  field.suction(tip, 0.02, 0.05);
  for (std::size_t i = 0; i < 5; ++i) {
    const Real expected = distance[i] <= 0.02 ? 0.08 * std::exp(-0.5) : 0.08;  // 0.048522
    EXPECT_NEAR(field.particles()[i].opacity, expected, 1e-16) << i;
  }
  for (int k = 1; k < 8; ++k) field.suction(tip, 0.02, 0.05);
  // 0.4 s: 0.08 e^{−4} = 1.47e-3, still above min_opacity
  EXPECT_EQ(field.size(), 5u);
  EXPECT_NEAR(field.particles()[0].opacity, 0.08 * std::exp(-4.0), 1e-16);
  field.suction(tip, 0.02, 0.05);  // 0.45 s: 0.08 e^{−4.5} = 8.9e-4: the three inside are gone
  ASSERT_EQ(field.size(), 2u);
  EXPECT_EQ(field.particles()[0].opacity, 0.08);
  EXPECT_EQ(field.particles()[1].opacity, 0.08);
  EXPECT_NEAR((field.particles()[0].position - tip).norm(), 0.0201, 1e-15);  // order kept
  EXPECT_NEAR((field.particles()[1].position - tip).norm(), 0.04, 1e-15);
}

// ---- Optical depth ---------------------------------------------------------------------------

TEST(SmokeOpticalDepth, OneParticleByHand) {
  SmokeField field(still(), 8);  // r = 3 mm, α = 0.08
  const Vec3 c(0.01, 0.02, 0.05);
  field.emit(c, Vec3::UnitZ(), 0.01);
  ASSERT_EQ(field.size(), 1u);
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY();
  EXPECT_NEAR(field.optical_depth(c - 0.1 * x, c + 0.1 * x), 0.08, 1e-15);  // through the centre
  EXPECT_NEAR(field.optical_depth(c + 0.1 * x, c - 0.1 * x), 0.08, 1e-15);  // either way
  // 2 mm off the centre: chord 2√(3² − 2²) = 4.472 mm of 6 mm → 0.08 · 0.745356 = 0.0596285
  EXPECT_NEAR(field.optical_depth(c - 0.1 * x + 0.002 * y, c + 0.1 * x + 0.002 * y), 0.0596285, 1e-7);
  EXPECT_EQ(field.optical_depth(c - 0.1 * x + 0.004 * y, c + 0.1 * x + 0.004 * y), 0.0);  // misses
  EXPECT_NEAR(field.optical_depth(c - 0.1 * x, c), 0.04, 1e-15);                    // ends at the centre
  EXPECT_NEAR(field.optical_depth(c, c + 0.001 * x), 0.08 / 6, 1e-15);              // 1 mm inside
  EXPECT_EQ(field.optical_depth(c + 0.01 * x, c + 0.1 * x), 0.0);                   // beyond it
  EXPECT_EQ(field.optical_depth(c, c), 0.0);
}

TEST(SmokeOpticalDepth, APlumeVeilsTheViewThroughItNotBesideIt) {
  SmokeField field(SmokeSettings{}, 12);  // the defaults
  const Vec3 burn(0, 0, 0);
  for (int k = 0; k < 1000; ++k) {  // 1 s of a 30 W cut (30 J into vapour), stepped at 1 ms
    field.emit(burn, Vec3::UnitZ(), 0.03);
    field.step(1e-3);
  }
  EXPECT_EQ(field.emitted(), 3000u);
  // The scope 8 cm to the side looking across the plume 2 cm above the burn, and the same
  // line of sight 8 cm further along y.
  const Real through = field.optical_depth(Vec3(-0.08, 0, 0.02), Vec3(0.08, 0, 0.02));
  const Real beside = field.optical_depth(Vec3(-0.08, 0.08, 0.02), Vec3(0.08, 0.08, 0.02));
  EXPECT_GT(through, 1.0);  // a thick fresh plume seen across its width
  EXPECT_LT(beside, 0.01 * through);
  // Venting for 3 s clears it at the combined rate, less what spreads away from the line.
  field.set_venting(true);
  for (int k = 0; k < 3000; ++k) field.step(1e-3);
  const Real vented = field.optical_depth(Vec3(-0.08, 0, 0.02), Vec3(0.08, 0, 0.02));
  EXPECT_LT(vented, through * std::pow(2.0, -3.0 / 5.0) * std::exp(-1.5));
}

// ---- Determinism -----------------------------------------------------------------------------

void script(SmokeField& field) {
  for (int k = 0; k < 400; ++k) {
    field.emit(Vec3(1e-4 * k, 0, 0), Vec3::UnitZ(), 0.037);
    field.step(1e-3 * (1 + k % 3));
    if (k == 200) field.set_venting(true);
    if (k % 50 == 0) field.suction(Vec3(0, 0, 0.02), 0.01, 0.01);
  }
}

TEST(SmokeDeterminism, SameSeedSameBitsOtherSeedOtherBits) {
  SmokeSettings s;
  s.capacity = 1024;  // so that it also replaces
  SmokeField a(s, 42), b(s, 42), c(s, 43);
  script(a);
  script(b);
  script(c);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 0u);
  EXPECT_EQ(a.emitted(), b.emitted());
  EXPECT_EQ(std::memcmp(a.particles().data(), b.particles().data(), a.size() * sizeof(SmokeParticle)), 0);
  // Another seed: other jitter and spread, so no particle is where it was (the suction, which
  // depends on where they are, may also leave another number).
  ASSERT_GT(c.size(), 0u);
  std::size_t same = 0;
  for (std::size_t i = 0; i < std::min(a.size(), c.size()); ++i)
    same += a.particles()[i].position == c.particles()[i].position;
  EXPECT_EQ(same, 0u);
}

TEST(SmokeSettingsCheck, RejectsSettingsThatCannotWork) {
  SmokeSettings s;
  s.capacity = 0;
  EXPECT_THROW(SmokeField(s, 1), std::invalid_argument);
  s = SmokeSettings{};
  s.drag_time = 0;
  EXPECT_THROW(SmokeField(s, 1), std::invalid_argument);
  s = SmokeSettings{};
  s.max_radius = 1e-3;  // below the birth radius
  EXPECT_THROW(SmokeField(s, 1), std::invalid_argument);
  s = SmokeSettings{};
  s.diffusion = -1;
  EXPECT_THROW(SmokeField(s, 1), std::invalid_argument);
  EXPECT_NO_THROW(SmokeField(SmokeSettings{}, 1));
  EXPECT_NO_THROW(SmokeField(still(), 1));
}

}  // namespace
}  // namespace trocar
