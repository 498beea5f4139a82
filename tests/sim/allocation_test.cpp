// No heap allocation inside Simulation::step after the first steps (DESIGN.md §3): a counting
// global operator new (for this whole test binary; it counts only while a window is open).
#include <gtest/gtest.h>

#include "support/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

#include "probe_scene.h"
#include "sheet_scene.h"
#include "trocar/sim/simulation.h"

using trocar::test::g_allocations;
using trocar::test::g_counting;

namespace trocar {
namespace {

/// Runs 150 steps (the buffers reach their size), then counts the heap allocations of the next
/// 100; every step detects and measures. Returns the contacts seen while counting.
std::uint32_t expect_no_allocation(Scene scene) {
  Simulation sim(std::move(scene.world), scene.settings);
  for (int n = 0; n < 150; ++n) sim.step(1e-3);
  g_allocations = 0;
  g_counting = true;
  std::uint32_t contacts = 0;
  for (int n = 0; n < 100; ++n) contacts += sim.step(1e-3).contacts;
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  return contacts;
}

TEST(SimulationAllocation, StepInContactAllocatesNothing) {
  ASSERT_EQ(test::probe_counted_allocations(), 2);  // the counting operator new is in use
  // A probe pressed into a closed ball for 0.1 s, then held.
  EXPECT_GT(expect_no_allocation(test::probe_scene(0.04, 0.024, 0.1)), 0u);
}

TEST(SimulationAllocation, StepThroughASheetAllocatesNothing) {
  // The open-tissue metrics (sheet side and crossing checks, sheet_crossing.cpp): pressed 4 mm
  // into the sheet for 0.1 s, then held.
  Scene scene = parse_scene(test::sheet_scene("[0.001, 0.002, 0.002]", "[0.001, 0.002, -0.002]", 0.1, 0.001),
                            "sheet.json", ".");
  ASSERT_TRUE(scene.settings.measure_penetration);
  EXPECT_GT(expect_no_allocation(std::move(scene)), 0u);
}

}  // namespace
}  // namespace trocar
