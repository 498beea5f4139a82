// Scripted motion through keyframes (core/motion.h): linear and smooth interpolation, against
// values computed by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "trocar/core/motion.h"

namespace trocar {
namespace {

Keyframe key(Real t, Real x) {
  Keyframe k;
  k.t = t;
  k.position = Vec3(x, 0, 0);
  return k;
}

Real x_at(const KeyframeMotion& m, Real t) { return m.sample(t).pose.translation.x(); }

/// Central-difference velocity (m/s) at t over ±h.
Real speed_at(const KeyframeMotion& m, Real t, Real h) { return (x_at(m, t + h) - x_at(m, t - h)) / (2 * h); }

TEST(KeyframeMotion, SmoothPassesThroughEveryKeyframeAndStartsAndEndsAtRest) {
  const std::vector<Keyframe> keys = {key(0, 0), key(0.3, 0.01), key(0.5, 0.004), key(1.0, 0.02)};
  const KeyframeMotion smooth(keys, Interpolation::kSmooth);
  for (const Keyframe& k : keys) EXPECT_NEAR(x_at(smooth, k.t), k.position.x(), 1e-15) << k.t;
  EXPECT_NEAR(speed_at(smooth, 1e-6, 1e-6), 0, 1e-5);  // one-sided at the ends: h00' = h01' = 0 there
  EXPECT_NEAR((x_at(smooth, 1.0) - x_at(smooth, 1.0 - 1e-6)) / 1e-6, 0, 1e-3);
  // Linear keeps its constant speed to the end: 0.016 m in 0.5 s.
  const KeyframeMotion linear(keys);
  EXPECT_NEAR((x_at(linear, 1.0) - x_at(linear, 1.0 - 1e-6)) / 1e-6, 0.032, 1e-9);
}

TEST(KeyframeMotion, SmoothVelocityIsContinuousAtAKeyframeWhereLinearJumps) {
  // 10 mm in 0.2 s (0.05 m/s), then 6 mm back in 0.2 s (-0.03 m/s): the tangent at 0.2 s is the
  // mean of the two, 0.01 m/s (under 3 × 0.03), on both sides of the keyframe.
  const std::vector<Keyframe> keys = {key(0, 0), key(0.2, 0.01), key(0.4, 0.004)};
  const KeyframeMotion smooth(keys, Interpolation::kSmooth), linear(keys);
  const Real h = 1e-5;
  EXPECT_NEAR((x_at(smooth, 0.2) - x_at(smooth, 0.2 - h)) / h, 0.01, 2e-5);
  EXPECT_NEAR((x_at(smooth, 0.2 + h) - x_at(smooth, 0.2)) / h, 0.01, 2e-5);
  EXPECT_NEAR((x_at(linear, 0.2) - x_at(linear, 0.2 - h)) / h, 0.05, 1e-9);
  EXPECT_NEAR((x_at(linear, 0.2 + h) - x_at(linear, 0.2)) / h, -0.03, 1e-9);
}

TEST(KeyframeMotion, SmoothIsExactAtConstantSpeedBetweenInteriorKeyframes) {
  // Evenly spaced in time and space: the tangents at the two interior keys equal the speed
  // (1 m/s), so the middle segment is the straight line at that speed.
  const KeyframeMotion smooth({key(0, 0), key(1, 1), key(2, 2), key(3, 3)}, Interpolation::kSmooth);
  EXPECT_NEAR(x_at(smooth, 1.25), 1.25, 1e-12);
  EXPECT_NEAR(x_at(smooth, 1.5), 1.5, 1e-12);
  // The first segment starts at rest: h01(0.5) = 0.5 plus h11(0.5)·1·1 = -0.125 → 0.375.
  EXPECT_NEAR(x_at(smooth, 0.5), 0.375, 1e-12);
}

TEST(KeyframeMotion, SmoothDoesNotOvershootAKeyframeWhereTheTipSlowsDown) {
  // Fast to 10 mm (0.1 m/s), then 0.1 mm more in 0.1 s (1 mm/s): the mean tangent (50.5 mm/s)
  // would carry the tip 0.75 mm past 10.1 mm; the Fritsch–Carlson bound (3 mm/s) keeps it
  // moving forward and short of the last keyframe.
  const KeyframeMotion smooth({key(0, 0), key(0.1, 0.01), key(0.2, 0.0101)}, Interpolation::kSmooth);
  Real previous = 0, highest = 0;
  for (int i = 0; i <= 2000; ++i) {
    const Real x = x_at(smooth, 0.2 * i / 2000);
    EXPECT_GE(x, previous - 1e-15) << i;
    previous = x;
    highest = std::max(highest, x);
  }
  EXPECT_LE(highest, 0.0101 + 1e-15);
}

TEST(KeyframeMotion, SmoothHoldsStayStill) {
  // A hold (two keyframes at the same place) does not move, and the motion leaves it at rest.
  const KeyframeMotion smooth({key(0, 0), key(0.2, 0.01), key(0.5, 0.01), key(0.7, 0.02)}, Interpolation::kSmooth);
  for (int i = 0; i <= 30; ++i) EXPECT_DOUBLE_EQ(x_at(smooth, 0.2 + 0.01 * i), 0.01) << i;
  EXPECT_NEAR((x_at(smooth, 0.5 + 1e-6) - x_at(smooth, 0.5)) / 1e-6, 0, 1e-3);
}

}  // namespace
}  // namespace trocar
