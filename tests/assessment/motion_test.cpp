// Motion metrics against hand-computed values on synthetic tip paths (docs/assessment.md).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "trocar/assessment/motion.h"

namespace trocar {
namespace {

constexpr Real kDt = 1e-3;

/// x(t) for t = 0, dt, …, duration (inclusive).
template <typename F>
std::vector<Vec3> sample(Real duration, F&& x) {
  std::vector<Vec3> p;
  const auto n = static_cast<std::size_t>(std::llround(duration / kDt));
  for (std::size_t k = 0; k <= n; ++k) p.push_back(x(static_cast<Real>(k) * kDt));
  return p;
}

TEST(Motion, AStraightLineIsItsLengthAndAllAlongAnAxisParallelToIt) {
  // 0.1 m along (3, 4, 0)/5 in 2 s.
  const Vec3 u(0.6, 0.8, 0);
  const auto p = sample(2, [&](Real t) { return Vec3(0.05 * t * u); });
  EXPECT_NEAR(path_length(p), 0.1, 1e-12);
  std::vector<Vec3> along(p.size(), u), across(p.size(), Vec3::UnitZ());
  EXPECT_NEAR(depth_path(p, along), 0.1, 1e-12);
  EXPECT_NEAR(depth_path(p, across), 0, 1e-15);
  // At 60° to the axis: cos 60° of the path.
  std::vector<Vec3> tilted(p.size(), Vec3(0.5 * u + std::sqrt(0.75) * Vec3::UnitZ()));
  EXPECT_NEAR(depth_path(p, tilted), 0.05, 1e-12);
}

TEST(Motion, ACircleAtKnownSpeedHasItsCircumferenceAndThatSpeed) {
  // r = 2 cm, one turn in 4 s: 2π·0.02 m, speed π·0.01 m/s.
  const Real r = 0.02, period = 4;
  const auto p = sample(period, [&](Real t) {
    const Real a = 2 * std::numbers::pi * t / period;
    return Vec3(r * std::cos(a), r * std::sin(a), 0.1);
  });
  // 4000 chords of 2r·sin(Δθ/2), Δθ = 2π/4000 (the arc 2πr less 1.3·10⁻⁸ m); the central
  // difference spans 2 sin Δθ·r over 2 dt (π·0.01 m/s less 1.3·10⁻⁸).
  const Real step = 2 * std::numbers::pi / 4000;
  EXPECT_NEAR(path_length(p), 4000 * 2 * r * std::sin(step / 2), 1e-13);
  EXPECT_NEAR(path_length(p), 2 * std::numbers::pi * r, 2e-8);
  std::vector<Real> v(p.size());
  tip_speeds(p, kDt, v);
  for (std::size_t k = 1; k + 1 < v.size(); ++k) ASSERT_NEAR(v[k], r * std::sin(step) / kDt, 1e-13) << k;
}

TEST(Motion, APauseOfKnownLengthIsIdleTimeAndNotPath) {
  // 1 s at 2 cm/s, 0.5 s still, 1 s at 2 cm/s: idle 0.5 s (± a sample at each edge).
  const auto p = sample(2.5, [](Real t) {
    const Real s = t < 1 ? t : t < 1.5 ? 1 : t - 0.5;
    return Vec3(0.02 * s, 0, 0);
  });
  std::vector<Real> v(p.size());
  tip_speeds(p, kDt, v);
  EXPECT_NEAR(idle_time(v, kDt, 0.005), 0.5, 2 * kDt);
  EXPECT_NEAR(path_length(p), 0.04, 1e-12);
  // Not present during the pause: the pause is not idle time (the instrument was out).
  std::vector<std::uint8_t> present(p.size(), 1);
  for (std::size_t k = 1005; k < 1495; ++k) present[k] = 0;
  EXPECT_NEAR(idle_time(v, kDt, 0.005, present), 0.5 - 490 * kDt, 3 * kDt);
}

TEST(Motion, AMinimumJerkReachHasTheClosedFormsDimensionlessJerk) {
  // x(τ) = D(10τ³ − 15τ⁴ + 6τ⁵): v = (D/T)·30τ²(1−τ)², peak 1.875 D/T, ∫|v''|² = 720 D²/T⁵, so
  // T³/v_peak² · ∫ = 720 / 1.875² = 204.8 and LDLJ = −ln 204.8 = −5.3221, whatever D and T.
  for (const Real T : {0.5, 2.0})
    for (const Real D : {0.01, 0.2}) {
      const auto p = sample(T, [&](Real t) {
        const Real s = t / T;
        return Vec3(D * (10 * s * s * s - 15 * s * s * s * s + 6 * s * s * s * s * s), 0, 0);
      });
      EXPECT_NEAR(log_dimensionless_jerk(p, kDt), -std::log(204.8), 0.01) << "T " << T << " D " << D;
      EXPECT_NEAR(log_dimensionless_jerk(p, kDt, 20), -std::log(204.8), 0.02) << "50 Hz";
    }
}

TEST(Motion, AHesitantReachIsLessSmoothThanAMinimumJerkOne) {
  // Two minimum-jerk halves with a stop between them (a sub-movement): more jerk per peak speed.
  const Real T = 1, D = 0.05;
  const auto mj = [](Real s) { return 10 * s * s * s - 15 * s * s * s * s + 6 * s * s * s * s * s; };
  const auto smooth = sample(T, [&](Real t) { return Vec3(D * mj(t / T), 0, 0); });
  const auto hesitant = sample(T, [&](Real t) {
    const Real s = t / T;
    return Vec3(s < 0.5 ? 0.5 * D * mj(2 * s) : 0.5 * D + 0.5 * D * mj(2 * s - 1), 0, 0);
  });
  const Real a = log_dimensionless_jerk(smooth, kDt), b = log_dimensionless_jerk(hesitant, kDt);
  // Each half: T/2, D/2, peak 1.875·D/T: ∫ = 2·720(D/2)²/(T/2)⁵ = 11520 D²/T⁵ → 11520/3.516 = 3276.8.
  EXPECT_NEAR(b, -std::log(3276.8), 0.02);
  EXPECT_LT(b, a - 2);
}

TEST(Motion, OutOfViewCountsOnlyWhilePresent) {
  const std::vector<std::uint8_t> present = {1, 1, 1, 0, 0, 1}, in_view = {1, 0, 0, 0, 1, 1};
  EXPECT_NEAR(out_of_view_time(present, in_view, 0.01), 0.02, 1e-15);
}

TEST(Motion, TooFewSamplesOrNoMotionGiveZeroNotNaN) {
  const std::vector<Vec3> still(100, Vec3(0.1, 0.2, 0.3)), few(3, Vec3::Zero());
  EXPECT_EQ(log_dimensionless_jerk(still, kDt), 0);
  EXPECT_EQ(log_dimensionless_jerk(few, kDt), 0);
  EXPECT_EQ(path_length(std::vector<Vec3>{}), 0);
}

}  // namespace
}  // namespace trocar
