#include "trocar/runtime/realtime.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <cerrno>
#include <cstring>

#include "trocar/runtime/clock.h"

namespace trocar {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

std::string make_current_thread_realtime(int priority, int cpu) {
  std::string warning;
  sched_param param{};
  param.sched_priority = priority;
  if (const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); e != 0)
    warning = std::string("SCHED_FIFO priority ") + std::to_string(priority) + " refused (" + std::strerror(e) +
              "): normal scheduling";
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (const int e = pthread_setaffinity_np(pthread_self(), sizeof(set), &set); e != 0)
      warning += (warning.empty() ? "" : "; ") + std::string("pinning to CPU ") + std::to_string(cpu) +
                 " refused (" + std::strerror(e) + ")";
  }
  return warning;
}

std::string lock_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    return std::string("mlockall refused (") + std::strerror(errno) + "): pages may fault in a tick";
  return {};
}

void wait_until(std::int64_t deadline_ns, std::int64_t spin_ns) {
  const std::int64_t sleep_to = deadline_ns - spin_ns;
  if (monotonic_ns() < sleep_to) {
    timespec ts{};
    ts.tv_sec = sleep_to / 1000000000LL;
    ts.tv_nsec = sleep_to % 1000000000LL;
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
  while (monotonic_ns() < deadline_ns) {
  }
}

namespace {
class SteadyClock final : public RuntimeClock {
 public:
  std::int64_t now_ns() override { return monotonic_ns(); }
  void wait_until(std::int64_t deadline_ns, std::int64_t spin_ns) override { trocar::wait_until(deadline_ns, spin_ns); }
};
}  // namespace

RuntimeClock& steady_clock() {
  static SteadyClock clock;
  return clock;
}

}  // namespace trocar
