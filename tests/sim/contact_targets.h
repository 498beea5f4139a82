#pragma once
// The contact targets of the core (docs/robustness.md): a run is stable, its penetration p99 is
// at most 0.5 mm and its max at most 1 mm, and no instrument vertex tunnels.
#include <gtest/gtest.h>

#include "trocar/study/robustness.h"

namespace trocar::test {

inline void expect_contact_targets(const SuiteRun& r) {
  EXPECT_TRUE(r.stable);
  EXPECT_LE(r.penetration_p99, 0.5e-3);
  EXPECT_LE(r.penetration_max, 1e-3);
  EXPECT_EQ(r.tunneling, 0u);
}

}  // namespace trocar::test
