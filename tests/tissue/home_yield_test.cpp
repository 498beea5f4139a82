// Plastic home springs (MassSpringMaterial::home_yield, docs/tissue.md "Home springs"): an anchor
// follows its vertex to the yield distance and no further (tests/sim/home_yield_test.cpp: the
// anchors in a simulated tissue).
#include <gtest/gtest.h>

#include <cmath>

#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {
namespace {

MassSpringSettings two_vertices(Real yield) {
  MassSpringSettings s;
  s.rest_positions = {Vec3::Zero(), Vec3::Zero()};
  s.home_positions = s.rest_positions;
  s.masses = {1e-3, 1e-3};
  s.inverse_masses = {0, 1e3};
  s.fixed = {1, 0};
  s.k_home = 1;
  s.home_yield = yield;
  return s;
}

TEST(HomeYield, AnAnchorFollowsItsVertexToTheYieldDistance) {
  MassSpringSettings s = two_vertices(0.005);
  MassSpringState state{{Vec3(0.008, 0, 0), Vec3(0, 0.008, 0)}, {Vec3::Zero(), Vec3::Zero()}};
  EXPECT_TRUE(yield_home(s, state));
  EXPECT_EQ(s.home_positions[0], Vec3::Zero());  // fixed: never moves
  EXPECT_NEAR((s.home_positions[1] - Vec3(0, 0.003, 0)).norm(), 0, 1e-15);  // 8 mm − 5 mm, along the stretch
  EXPECT_EQ(s.rest_positions[1], Vec3::Zero());  // the rest shape is the rest shape
  const Vec3 anchor = s.home_positions[1];
  yield_home(s, state);  // at the yield now (to rounding): stays
  EXPECT_LT((s.home_positions[1] - anchor).norm(), 1e-17);
  state.positions[1] = Vec3(0, 0.006, 0.0039);  // 4.9 mm from the anchor: within
  EXPECT_FALSE(yield_home(s, state));
}

TEST(HomeYield, ZeroYieldOrNoHomeSpringsIsElastic) {
  MassSpringSettings s = two_vertices(0);
  const MassSpringState state{{Vec3::Zero(), Vec3(1, 0, 0)}, {Vec3::Zero(), Vec3::Zero()}};
  EXPECT_FALSE(yield_home(s, state));
  s.home_yield = 0.001;
  s.k_home = 0;
  EXPECT_FALSE(yield_home(s, state));
  EXPECT_EQ(s.home_positions[1], Vec3::Zero());
}

}  // namespace
}  // namespace trocar
