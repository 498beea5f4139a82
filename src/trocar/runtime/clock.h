#pragma once
/// The time the runtime's loops read and wait on. The real one is the steady clock; a test hands
/// the runtime a clock it moves itself (tests/support/manual_clock.h), so that the ticks and steps
/// of a run follow the test's time instead of the machine's load.
#include <cstdint>

namespace trocar {

class RuntimeClock {
 public:
  virtual ~RuntimeClock() = default;
  /// The current time (ns; any fixed origin).
  virtual std::int64_t now_ns() = 0;
  /// Returns once now_ns() ≥ deadline_ns; a real clock may spin for the last spin_ns of it.
  virtual void wait_until(std::int64_t deadline_ns, std::int64_t spin_ns) = 0;
};

/// The steady clock through monotonic_ns() and wait_until() of realtime.h (no lock, no system
/// call but the sleep). Shared: it has no state.
RuntimeClock& steady_clock();

}  // namespace trocar
