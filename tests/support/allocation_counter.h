#pragma once
// A counting global operator new for the "no allocation after warm-up" tests (docs/architecture.md
// "Conventions"). Linking trocar_test_allocation_counter replaces operator new/delete for the whole
// test binary; allocations are counted only while g_counting is true.
#include <atomic>

namespace trocar::test {

/// While true, every global operator new / new[] call adds one to g_allocations.
extern std::atomic<bool> g_counting;
/// The number of allocations counted so far (reset it by assigning 0).
extern std::atomic<long> g_allocations;

/// Allocations counted while making one std::vector<int>(10) through new: 2 (the vector
/// object and its buffer) when the counting operator new is the one in use.
long probe_counted_allocations();

}  // namespace trocar::test
