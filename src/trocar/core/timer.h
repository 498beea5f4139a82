#pragma once
/// Monotonic wall-clock timer for per-module timing.
#include <chrono>

namespace trocar {

/// Measures elapsed time from construction or the last restart(); no allocation, no locks.
class Timer {
 public:
  Timer() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  /// Seconds since the start.
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// Microseconds since the start.
  double microseconds() const { return seconds() * 1e6; }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

}  // namespace trocar
