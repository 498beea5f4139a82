// No heap allocation inside MassSpringIntegrator::step (docs/architecture.md "Conventions"), not
// even on the first step: a counting global operator new (replacing the one of this whole test
// binary; it only counts while a window is open) around step() for every integrator, with contacts
// present, and around the loads' clear() and add_force() that precede each step.
#include <gtest/gtest.h>

#include "support/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

#include "trocar/core/cpu_features.h"
#include "trocar/mesh/generate.h"
#include "trocar/tissue/integrator.h"

using trocar::test::g_allocations;
using trocar::test::g_counting;

namespace trocar {
namespace {

TEST(IntegratorAllocation, StepNeverAllocates) {
  ASSERT_EQ(test::probe_counted_allocations(), 2);  // the counting operator new is in use

  MassSpringMaterial m;
  m.mass = 0.1;
  m.k_area = 10;
  m.k_volume = 1e4;
  m.k_home = 1;
  FixedSelection fixed;
  fixed.indices = {0, 1, 2};
  const MassSpringSettings s_area = MassSpringSettings::build(make_icosphere(0.05, 2), m, fixed, Vec3(0, 0, -9.81));
  MassSpringMaterial no_area = m;
  no_area.k_area = 0;
  const MassSpringSettings s_no_area =
      MassSpringSettings::build(make_icosphere(0.05, 2), no_area, fixed, Vec3(0, 0, -9.81));
  // The explicit ones pass by pass and as one sweep (which skips the area term: off in those runs).
  struct Run {
    IntegratorKind kind;
    bool sweep;
  };
  for (const Run run : {Run{IntegratorKind::kExplicitEuler, false}, Run{IntegratorKind::kSemiImplicitEuler, false},
                        Run{IntegratorKind::kExplicitEuler, true}, Run{IntegratorKind::kSemiImplicitEuler, true},
                        Run{IntegratorKind::kImplicitEuler, false}, Run{IntegratorKind::kXpbd, false}}) {
    const IntegratorKind kind = run.kind;
    const MassSpringSettings& s = run.sweep ? s_no_area : s_area;
    MassSpringState state = MassSpringState::at_rest(s);
    MassSpringIntegrator integ(s, kind);
    integ.set_explicit_sweep(run.sweep);
    if (run.sweep && cpu_has_avx2_fma()) {
      ASSERT_TRUE(integ.explicit_sweep());
    }
    TissueLoads loads;
    loads.reset(s.vertex_count(), 16);
    g_allocations = 0;
    for (int n = 0; n < 50; ++n) {
      g_counting = true;  // the loads' clear and add_force too: they run every step of a simulation
      loads.clear();
      for (std::uint32_t t = 0; t < 8; ++t) {
        const Triangle& tri = s.triangles[t * 10];
        loads.contacts.push_back({{tri[0], tri[1], tri[2]}, {0.2, 0.3, 0.5}, Vec3(0, 0, 1), 500, 0.01});
        loads.add_force(tri[0], Vec3(0, 0, 0.01));
      }
      const StepStats stats = integ.step(state, loads, 1e-4);
      g_counting = false;
      ASSERT_TRUE(stats.finite);
      if (kind == IntegratorKind::kImplicitEuler && n > 0) {
        EXPECT_GT(stats.cg_iterations, 0);
      }
    }
    EXPECT_EQ(g_allocations.load(), 0) << integrator_name(kind) << (run.sweep ? " (sweep)" : "");
  }
}

}  // namespace
}  // namespace trocar
