// No heap allocation in detect() after warm-up (DESIGN.md §3): a counting global operator new
// (replacing the one of this whole test binary; it only counts while a window is open).
#include <gtest/gtest.h>

#include "support/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

#include "scene_util.h"
#include "trocar/mesh/generate.h"

using trocar::test::g_allocations;
using trocar::test::g_counting;

namespace trocar {
namespace {

TEST(CollisionAllocation, DetectAllocatesNothingAfterWarmUp) {
  ASSERT_EQ(test::probe_counted_allocations(), 2);  // the counting operator new is in use

  test::CuttingScene cut(make_icosphere(0.05, 4), make_capsule(0.004, 0.04, 12, 4), 0.006, 0.002, 0.001);
  cut.scene.add(test::translated(make_box(0.05, 0.05, 0.05), Vec3(0, 0, -0.06)), ObjectRole::kRigid);
  const std::vector<CollisionObject> objects = cut.scene.objects();
  for (const BroadPhaseKind kind : {BroadPhaseKind::kOhc, BroadPhaseKind::kBvh}) {
    CollisionDetector detector(kind);
    std::vector<Contact> out;
    // Warm-up: the frames the loop below will see, so every buffer reaches its size.
    for (int f = 0; f < 6; ++f) {
      cut.set_frame(f);
      detector.detect(objects, out);
    }
    long allocations = 0;
    std::size_t contacts = 0;
    for (int f = 0; f < 6; ++f) {
      cut.set_frame(f);  // writes positions in place: the views stay valid
      g_allocations = 0;
      g_counting = true;
      detector.detect(objects, out);
      g_counting = false;
      allocations += g_allocations.load();
      contacts += out.size();
    }
    EXPECT_EQ(allocations, 0) << broad_phase_name(kind);
    EXPECT_GT(contacts, 0u) << broad_phase_name(kind);
  }
}

}  // namespace
}  // namespace trocar
