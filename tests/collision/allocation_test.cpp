// No heap allocation in detect() after warm-up (docs/architecture.md "Conventions"): a counting
// global operator new (replacing the one of this whole test binary; it only counts while a window
// is open).
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
  // OHC twice: the default (cluster-pair path here) and with the cell hash always.
  OhcSettings hash_settings;
  hash_settings.max_pair_tests_per_primitive = 0;
  for (const int variant : {0, 1, 2}) {
    const BroadPhaseKind kind = variant == 2 ? BroadPhaseKind::kBvh : BroadPhaseKind::kOhc;
    CollisionDetector detector = variant == 1 ? CollisionDetector(hash_settings) : CollisionDetector(kind);
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
    EXPECT_EQ(allocations, 0) << broad_phase_name(kind) << " variant " << variant;
    EXPECT_GT(contacts, 0u) << broad_phase_name(kind) << " variant " << variant;
  }
}

}  // namespace
}  // namespace trocar
