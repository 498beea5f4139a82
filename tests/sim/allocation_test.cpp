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

TEST(SimulationAllocation, StepInContactAllocatesNothing) {
  ASSERT_EQ(test::probe_counted_allocations(), 2);  // the counting operator new is in use

  // Press in for 0.1 s, then hold; every step detects and measures penetration.
  Scene scene = test::probe_scene(0.04, 0.024, 0.1);
  Simulation sim(std::move(scene.world), scene.settings);
  for (int n = 0; n < 150; ++n) sim.step(1e-3);  // buffers reach their size
  g_allocations = 0;
  g_counting = true;
  std::uint32_t contacts = 0;
  for (int n = 0; n < 100; ++n) contacts += sim.step(1e-3).contacts;
  g_counting = false;
  EXPECT_GT(contacts, 0u);
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(SimulationAllocation, StepThroughASheetAllocatesNothing) {
  // The open-tissue metrics (sheet side and crossing checks, sheet_crossing.cpp): pressed 4 mm
  // into the sheet for 0.1 s, then held, detection every step.
  Scene scene = parse_scene(test::sheet_scene("[0.001, 0.002, 0.002]", "[0.001, 0.002, -0.002]", 0.1, 0.001),
                            "sheet.json", ".");
  ASSERT_TRUE(scene.settings.measure_penetration);
  Simulation sim(std::move(scene.world), scene.settings);
  for (int n = 0; n < 150; ++n) sim.step(1e-3);  // buffers reach their size
  g_allocations = 0;
  g_counting = true;
  std::uint32_t contacts = 0;
  for (int n = 0; n < 100; ++n) contacts += sim.step(1e-3).contacts;
  g_counting = false;
  EXPECT_GT(contacts, 0u);
  EXPECT_EQ(g_allocations.load(), 0);
}

}  // namespace
}  // namespace trocar
