// core/statistics.h: quantiles by linear interpolation (Hyndman & Fan definition 7), hand-computed.
// core/stability.h: the energy bound and the finite check.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "trocar/core/stability.h"
#include "trocar/core/statistics.h"

namespace trocar {
namespace {

TEST(Statistics, MedianOfOddCountIsTheMiddleSample) {
  const std::vector<double> v = {5, 1, 3};
  EXPECT_EQ(median(v), 3.0);
}

TEST(Statistics, MedianOfEvenCountIsTheMeanOfTheMiddleTwo) {
  const std::vector<double> v = {4, 1, 3, 2};  // sorted 1 2 3 4: (2 + 3) / 2
  EXPECT_EQ(median(v), 2.5);
}

TEST(Statistics, QuantileInterpolatesBetweenOrderStatistics) {
  // Sorted 10 20 30 40 50; h = 4q.
  const std::vector<double> v = {50, 10, 40, 20, 30};
  EXPECT_EQ(quantile(v, 0.0), 10.0);
  EXPECT_EQ(quantile(v, 1.0), 50.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.1), 14.0);   // h = 0.4: 10 + 0.4·10
  EXPECT_DOUBLE_EQ(quantile(v, 0.99), 49.6);  // h = 3.96: 40 + 0.96·10
  EXPECT_EQ(quantile(v, 2.0), 50.0);          // clamped to 1
  EXPECT_EQ(quantile(v, -1.0), 10.0);         // clamped to 0
}

TEST(Statistics, P99OfHundredSamplesInterpolatesTheTopTwo) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // 1..100, reversed
  EXPECT_DOUBLE_EQ(quantile(v, 0.99), 99.01);     // h = 98.01: 99 + 0.01·1
  EXPECT_DOUBLE_EQ(median(v), 50.5);
}

TEST(Statistics, EmptyAndSingleSample) {
  const std::vector<double> none;
  EXPECT_EQ(quantile(none, 0.5), 0.0);
  EXPECT_EQ(mean(none), 0.0);
  const Summary s = summarize(none);
  EXPECT_EQ(s.median, 0.0);
  EXPECT_EQ(s.max, 0.0);
  const std::vector<double> one = {7};
  EXPECT_EQ(quantile(one, 0.99), 7.0);
  EXPECT_EQ(median(one), 7.0);
}

TEST(Statistics, SummaryAndMean) {
  const std::vector<double> v = {1, 2, 3, 4, 10};
  const Summary s = summarize(v);
  EXPECT_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.p99, 9.76);  // h = 3.96: 4 + 0.96·6
  EXPECT_EQ(s.max, 10.0);
  EXPECT_DOUBLE_EQ(mean(v), 4.0);
}

TEST(Stability, EnergyBoundIsHalfTheMassAtTheSpeedBound) {
  EXPECT_DOUBLE_EQ(stable_energy_bound(0.3), 0.5 * 0.3 * 100.0);  // 15 J for 0.3 kg at 10 m/s
  EXPECT_TRUE(is_stable(true, 15.0, 0.3));
  EXPECT_FALSE(is_stable(true, 15.0001, 0.3));
  EXPECT_FALSE(is_stable(false, 0.0, 0.3));
  EXPECT_FALSE(is_stable(true, std::numeric_limits<double>::quiet_NaN(), 0.3));
  EXPECT_FALSE(is_stable(true, std::numeric_limits<double>::infinity(), 0.3));
  EXPECT_TRUE(is_stable(true, 0.0, 0.0));  // no tissue: nothing can run away
  // Per tissue: the scene's energy within its bound, one tissue's RMS speed at or over 10 m/s.
  EXPECT_TRUE(is_stable(true, 0.5, 4.0, 10.0));
  EXPECT_FALSE(is_stable(true, 0.5, 4.0, 10.0001));
  EXPECT_FALSE(is_stable(true, 15.0001, 0.3, 1.0));  // and still the scene's bound
}

}  // namespace
}  // namespace trocar
