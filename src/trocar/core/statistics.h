#pragma once
/// Summary statistics of samples (step times, penetration depths, ...), one rule for the whole
/// code base so that a "median" or a "p99" means the same in every report.
///
/// quantile(): linear interpolation between the order statistics, the definition R and NumPy use
/// by default (Hyndman & Fan 1996, "Sample quantiles in statistical packages", definition 7): with
/// the n samples sorted as x₀ ≤ … ≤ xₙ₋₁ and h = (n − 1)·q, Q(q) = x⌊h⌋ + (h − ⌊h⌋)(x⌊h⌋₊₁ − x⌊h⌋).
/// So Q(0) is the minimum, Q(1) the maximum, and the median of an even count is the mean of the
/// two middle samples. Empty input gives 0 (a report's "no samples").
#include <span>
#include <vector>

namespace trocar {

/// The q-quantile (q in [0, 1], clamped) of `samples` by linear interpolation; 0 when empty.
double quantile(std::span<const double> samples, double q);
/// quantile(samples, 0.5): the middle sample, or the mean of the two middle ones for an even count.
double median(std::span<const double> samples);
/// The arithmetic mean; 0 when empty.
double mean(std::span<const double> samples);

/// median, p99 and max of one series, as the reports print them.
struct Summary {
  double median = 0;
  double p99 = 0;
  double max = 0;
};
/// The summary of `samples` (all 0 when empty).
Summary summarize(std::span<const double> samples);

}  // namespace trocar
