#pragma once
/// Fixed-size timing histograms for the performance monitor (the seed's CPerformanceMonitor):
/// one writer adds samples without allocating; quantiles are read after the writer stopped.
#include <array>
#include <cstdint>

namespace trocar {

/// Log-spaced bins from 0.01 µs to 1 s (200 per decade: a quantile is within 0.6 % of the true
/// value), plus exact count, sum and maximum. Plain data: copy it to read it elsewhere.
class TimingHistogram {
 public:
  static constexpr double kMinUs = 0.01;        ///< lower edge of the first bin (µs)
  static constexpr int kBinsPerDecade = 200;    ///< resolution: bins 1.2 % wide
  static constexpr int kDecades = 8;            ///< 0.01 µs … 1e6 µs
  static constexpr int kBins = kBinsPerDecade * kDecades;

  /// Adds one sample (µs). Values below the range go to the first bin, above it to the last.
  void add(double us);
  /// The q-quantile (0 ≤ q ≤ 1) in µs: the geometric middle of the bin holding it; 0 if empty.
  double quantile(double q) const;
  double median() const { return quantile(0.5); }   ///< µs
  double p99() const { return quantile(0.99); }     ///< µs
  double max() const { return max_; }              ///< µs, exact
  double mean() const { return count_ ? sum_ / static_cast<double>(count_) : 0; }  ///< µs, exact
  std::uint64_t count() const { return count_; }    ///< samples
  /// Samples above `us` (counted from the bins: exact for bin edges, else within one bin).
  std::uint64_t count_above(double us) const;
  /// Adds another histogram's samples.
  void merge(const TimingHistogram& other);

 private:
  std::array<std::uint32_t, kBins> bins_{};
  std::uint64_t count_ = 0;
  double sum_ = 0;
  double max_ = 0;
};

}  // namespace trocar
