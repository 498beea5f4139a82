// TissueLoads: add_force accumulates and records each loaded vertex once; clear() zeroes those
// and only those (the rest were never written) and empties the list and the contacts; reset()
// zeroes everything; before reset there are no forces (the integrators then add none).
#include <gtest/gtest.h>

#include <vector>

#include "trocar/tissue/state.h"

namespace trocar {
namespace {

TEST(TissueLoads, AddForceAccumulatesAndRecordsEachVertexOnce) {
  TissueLoads loads;
  EXPECT_TRUE(loads.forces().empty());
  loads.reset(6, 2);
  ASSERT_EQ(loads.forces().size(), 6u);
  loads.add_force(4, Vec3(1, 2, 3));
  loads.add_force(1, Vec3(0.5, 0, 0));
  loads.add_force(4, Vec3(-0.25, 0, 1));
  EXPECT_EQ(loads.forces()[4], Vec3(0.75, 2, 4));
  EXPECT_EQ(loads.forces()[1], Vec3(0.5, 0, 0));
  for (const std::size_t i : {0, 2, 3, 5}) EXPECT_EQ(loads.forces()[i], Vec3::Zero());
  const std::vector<std::uint32_t> loaded(loads.loaded_vertices().begin(), loads.loaded_vertices().end());
  EXPECT_EQ(loaded, (std::vector<std::uint32_t>{4, 1}));
}

TEST(TissueLoads, ClearZeroesTheLoadedVerticesAndEmptiesTheLists) {
  TissueLoads loads;
  loads.reset(5, 4);
  loads.add_force(2, Vec3(1, 1, 1));
  loads.add_force(0, Vec3(0, 0, -9));
  loads.contacts.push_back(ContactJacobian{});
  loads.clear();
  for (const Vec3& f : loads.forces()) EXPECT_EQ(f, Vec3::Zero());
  EXPECT_TRUE(loads.loaded_vertices().empty());
  EXPECT_TRUE(loads.contacts.empty());
  // A vertex loaded again after the clear is recorded again, with only the new force.
  loads.add_force(2, Vec3(0, 3, 0));
  EXPECT_EQ(loads.forces()[2], Vec3(0, 3, 0));
  ASSERT_EQ(loads.loaded_vertices().size(), 1u);
  EXPECT_EQ(loads.loaded_vertices()[0], 2u);
  // reset() starts over at the new size.
  loads.reset(3, 0);
  EXPECT_EQ(loads.forces().size(), 3u);
  for (const Vec3& f : loads.forces()) EXPECT_EQ(f, Vec3::Zero());
  EXPECT_TRUE(loads.loaded_vertices().empty());
}

}  // namespace
}  // namespace trocar
