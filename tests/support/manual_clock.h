#pragma once
// A clock for the runtime that moves only when the test says so. The runtime's loops park in
// wait_until(); the test moves time with advance() and then settle()s: waits until every loop is
// parked again on a deadline still ahead, so that what the loops did in between is over and can
// be counted exactly, however slow or busy the machine is.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "trocar/runtime/clock.h"

namespace trocar::test {

class ManualClock final : public RuntimeClock {
 public:
  ManualClock() { parked_.reserve(8); }
  std::int64_t now_ns() override {
    std::lock_guard<std::mutex> lock(mutex_);
    return now_;
  }
  void wait_until(std::int64_t deadline_ns, std::int64_t /*spin_ns*/) override {
    std::unique_lock<std::mutex> lock(mutex_);
    parked_.push_back(deadline_ns);
    changed_.notify_all();
    changed_.wait(lock, [&] { return now_ >= deadline_ns; });
    parked_.erase(std::find(parked_.begin(), parked_.end(), deadline_ns));
  }
  /// Moves time forward by `ns` and wakes the loops whose deadline has come.
  void advance(std::int64_t ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    now_ += ns;
    changed_.notify_all();
  }
  /// Waits until `loops` threads are parked on deadlines after now. False after `limit` (a loop
  /// that hangs or never parks): the caller fails with its own message.
  [[nodiscard]] bool settle(int loops, std::chrono::seconds limit = std::chrono::seconds(30)) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, limit, [&] {
      return std::count_if(parked_.begin(), parked_.end(), [&](std::int64_t d) { return d > now_; }) == loops;
    });
  }
  /// True when no loop is about to wake (none parked on a deadline that has come) and at least
  /// one is parked on a deadline ahead: moving time now makes no loop late.
  bool quiet() {
    std::lock_guard<std::mutex> lock(mutex_);
    return !parked_.empty() && std::all_of(parked_.begin(), parked_.end(), [&](std::int64_t d) { return d > now_; });
  }
  /// The earliest deadline a loop is parked on (now when none is).
  std::int64_t next_deadline() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::int64_t next = INT64_MAX;
    for (std::int64_t d : parked_)
      if (d > now_) next = std::min(next, d);
    return next == INT64_MAX ? now_ : next;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::int64_t now_ = 0;
  std::vector<std::int64_t> parked_;  // deadlines of the threads waiting now
};

/// request_stop() on a runtime whose run() is on `thread` and moves `clock` on by `step_ns` at a
/// time, whenever the loops are quiet(), until run() has returned (polled, up to 30 s of wall time); joins. False if it never
/// ended (then it still joins: the test's timeout names the hang).
template <typename Runtime>
bool stop_and_join(Runtime& runtime, ManualClock& clock, std::thread& thread, std::int64_t step_ns) {
  if (!thread.joinable()) return true;
  runtime.request_stop();
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (runtime.live().running.load() && std::chrono::steady_clock::now() < limit) {
    if (clock.quiet()) clock.advance(step_ns);  // each loop's last period is on time
    else std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const bool ended = !runtime.live().running.load();
  thread.join();
  return ended;
}

/// Runs `runtime.run()` on its own thread on `clock` (which the runtime's settings name): to its
/// start, `periods` periods of `period_ns` one at a time (each until `loops` loops are parked
/// again: 2 multirate, 1 lock-step), then one more to stop. Returns run()'s report; a loop that
/// hangs fails the test.
template <typename Runtime>
auto run_for_periods(Runtime& runtime, ManualClock& clock, int loops, int periods, std::int64_t period_ns) {
  decltype(runtime.run()) report;
  std::thread thread([&] { report = runtime.run(); });
  bool parked = clock.settle(loops);
  if (parked) {
    clock.advance(clock.next_deadline() - clock.now_ns());
    parked = clock.settle(loops);
  }
  for (int i = 1; i < periods && parked; ++i) {
    clock.advance(period_ns);
    parked = clock.settle(loops);
  }
  EXPECT_TRUE(parked) << "a runtime loop did not park again within 30 s";
  EXPECT_TRUE(stop_and_join(runtime, clock, thread, period_ns)) << "run() did not end within 30 s of request_stop";
  return report;
}

}  // namespace trocar::test
