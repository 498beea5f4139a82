#include "trocar/core/statistics.h"

#include <algorithm>
#include <cmath>

namespace trocar {

double quantile(std::span<const double> samples, double q) {
  if (samples.empty()) return 0;
  std::vector<double> v(samples.begin(), samples.end());
  const double h = static_cast<double>(v.size() - 1) * std::clamp(q, 0.0, 1.0);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  // Two partial selections instead of a full sort: x⌊h⌋, then the smallest above it.
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
  const double below = v[lo];
  if (hi == lo) return below;
  const double above = *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(hi), v.end());
  return below + (h - static_cast<double>(lo)) * (above - below);
}

double median(std::span<const double> samples) { return quantile(samples, 0.5); }

double mean(std::span<const double> samples) {
  if (samples.empty()) return 0;
  double sum = 0;
  for (const double x : samples) sum += x;
  return sum / static_cast<double>(samples.size());
}

Summary summarize(std::span<const double> samples) {
  if (samples.empty()) return {};
  return {median(samples), quantile(samples, 0.99), *std::max_element(samples.begin(), samples.end())};
}

}  // namespace trocar
