#include "trocar/runtime/histogram.h"

#include <algorithm>
#include <cmath>

namespace trocar {
namespace {

int bin_of(double us) {
  if (!(us > TimingHistogram::kMinUs)) return 0;
  const double b = std::log10(us / TimingHistogram::kMinUs) * TimingHistogram::kBinsPerDecade;
  return std::min(static_cast<int>(b), TimingHistogram::kBins - 1);
}

double lower_edge(int bin) { return TimingHistogram::kMinUs * std::pow(10.0, double(bin) / TimingHistogram::kBinsPerDecade); }

}  // namespace

void TimingHistogram::add(double us) {
  ++bins_[static_cast<std::size_t>(bin_of(us))];
  ++count_;
  sum_ += us;
  max_ = std::max(max_, us);
}

double TimingHistogram::quantile(double q) const {
  if (count_ == 0) return 0;
  const double target = std::clamp(q, 0.0, 1.0) * static_cast<double>(count_);
  std::uint64_t seen = 0;
  for (int b = 0; b < kBins; ++b) {
    seen += bins_[static_cast<std::size_t>(b)];
    if (static_cast<double>(seen) >= target && seen > 0)
      return std::min(max_, std::sqrt(lower_edge(b) * lower_edge(b + 1)));
  }
  return max_;
}

std::uint64_t TimingHistogram::count_above(double us) const {
  std::uint64_t n = 0;
  for (int b = bin_of(us) + 1; b < kBins; ++b) n += bins_[static_cast<std::size_t>(b)];
  return n;
}

void TimingHistogram::merge(const TimingHistogram& other) {
  for (int b = 0; b < kBins; ++b) bins_[static_cast<std::size_t>(b)] += other.bins_[static_cast<std::size_t>(b)];
  count_ += other.count_;
  sum_ += other.sum_;
  max_ = std::max(max_, other.max_);
}

}  // namespace trocar
