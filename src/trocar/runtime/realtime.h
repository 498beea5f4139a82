#pragma once
/// Real-time scheduling where the system allows it, and the periodic wait of the haptic and
/// physics loops.
#include <cstdint>
#include <string>

namespace trocar {

/// Steady-clock time (ns). A vDSO read: no system call.
std::int64_t monotonic_ns();

/// Asks for SCHED_FIFO at `priority` (below the kernel's interrupt threads, which run at 50 on a
/// PREEMPT_RT kernel: the haptic thread takes 49, physics 48) and pins the calling thread to
/// `cpu` (< 0: no pinning). Returns "" when both worked, else a one-line warning saying what was
/// refused and that normal scheduling is used (e.g. without CAP_SYS_NICE or an rtprio limit).
std::string make_current_thread_realtime(int priority, int cpu);

/// Locks the process's pages in memory (mlockall) so that a page fault never stalls a tick.
/// Returns "" or a one-line warning.
std::string lock_memory();

/// Waits until the absolute steady-clock time `deadline_ns`: clock_nanosleep(TIMER_ABSTIME)
/// until `spin_ns` before it, then polls the clock (the sleep's wake-up latency on a
/// non-real-time kernel is 50–100 µs; the spin takes it out). The only system call of a tick.
void wait_until(std::int64_t deadline_ns, std::int64_t spin_ns);

}  // namespace trocar
