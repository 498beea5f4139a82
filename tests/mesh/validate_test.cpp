#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mesh_test_util.h"
#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

TEST(Validate, TetrahedronIsClean) {
  const MeshReport r = validate(test::tetrahedron());
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.triangles, 4u);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.orientation, Orientation::kOutward);
  EXPECT_NEAR(r.signed_volume, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(r.area, 1.5 + std::sqrt(3.0) / 2, 1e-14);
  EXPECT_EQ(r.bounds.min, Vec3(0, 0, 0));
  EXPECT_EQ(r.bounds.max, Vec3(1, 1, 1));
  EXPECT_TRUE(r.defects().empty());
  EXPECT_TRUE(r.is_clean());
}

TEST(Validate, CubeWithOneFaceRemoved) {
  TriMesh m = test::unit_cube();
  m.triangles.erase(m.triangles.begin() + 2, m.triangles.begin() + 4);
  const MeshReport r = validate(m);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.orientation, Orientation::kUndefined);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_NEAR(r.area, 5.0, 1e-14);
  EXPECT_FALSE(r.is_clean());
  EXPECT_TRUE(r.is_clean_open());
  ASSERT_EQ(r.defects().size(), 1u);
  EXPECT_EQ(r.defects()[0], "4 boundary edges (open surface)");
}

TEST(Validate, InsideOutCube) {
  TriMesh m = test::unit_cube();
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  const MeshReport r = validate(m);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_NEAR(r.signed_volume, -1.0, 1e-14);
  EXPECT_EQ(r.orientation, Orientation::kInward);
  EXPECT_FALSE(r.is_clean());
}

TEST(Validate, OneFlippedTriangleGivesThreeInconsistentEdges) {
  TriMesh m = test::unit_cube();
  std::swap(m.triangles[5][1], m.triangles[5][2]);
  const MeshReport r = validate(m);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.orientation, Orientation::kUndefined);
  EXPECT_FALSE(r.is_clean());
}

TEST(Validate, BowTie) {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};
  const MeshReport r = validate(m);
  EXPECT_EQ(r.nonmanifold_vertices, 1u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.boundary_edges, 6u);
}

TEST(Validate, FinOnACubeIsNonManifold) {
  TriMesh m = test::unit_cube();
  m.positions.emplace_back(0.5, -1, 0.5);
  m.triangles.push_back({0, 1, 8});  // a third triangle on the edge 0–1
  const MeshReport r = validate(m);
  EXPECT_EQ(r.nonmanifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 2u);
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.manifold);
}

TEST(Validate, DuplicateTrianglesInAnyOrder) {
  TriMesh m = test::tetrahedron();
  m.triangles.push_back({2, 1, 0});  // same set as {0,2,1}, opposite winding
  m.triangles.push_back({1, 0, 2});  // same set, same winding
  const MeshReport r = validate(m);
  EXPECT_EQ(r.duplicate_triangles, 2u);
  EXPECT_EQ(r.nonmanifold_edges, 3u);  // the bottom face's edges now have 4 triangles
}

TEST(Validate, DuplicateAndNearDuplicateVertices) {
  TriMesh m = test::tetrahedron();
  m.positions.push_back(m.positions[1]);                       // exact copy of vertex 1
  m.positions.push_back(m.positions[2] + Vec3(1e-9, 0, 0));   // near copy of vertex 2
  m.positions.emplace_back(-0.0, 0.0, 0.0);                    // −0 == +0: copy of vertex 0
  const MeshReport r = validate(m);
  EXPECT_EQ(r.duplicate_vertices, 2u);
  EXPECT_EQ(r.near_duplicate_vertices, 1u);
  EXPECT_EQ(r.unused_vertices, 3u);
  EXPECT_NEAR(r.near_duplicate_tolerance, 1e-6 * std::sqrt(3.0), 1e-20);
}

TEST(Validate, DegenerateTriangles) {
  TriMesh m = test::tetrahedron();
  m.positions.emplace_back(0.5, 0, 0);  // on edge 0–1
  m.triangles.push_back({0, 4, 1});     // zero area
  m.triangles.push_back({2, 2, 3});     // repeated index
  const MeshReport r = validate(m);
  EXPECT_EQ(r.degenerate_triangles, 2u);
  EXPECT_FALSE(r.closed);
}

TEST(Validate, OutOfRangeAndNonFiniteDoNotCrash) {
  TriMesh m = test::tetrahedron();
  m.triangles.push_back({0, 1, 99});
  m.triangles.push_back({4000000000u, 1, 2});
  m.positions.emplace_back(std::numeric_limits<Real>::quiet_NaN(), 0, 0);
  m.positions.emplace_back(1, 1, 1);
  m.triangles.push_back({4, 5, 0});
  const MeshReport r = validate(m);
  EXPECT_EQ(r.triangles, 7u);
  EXPECT_EQ(r.out_of_range_triangles, 2u);
  EXPECT_EQ(r.nonfinite_vertices, 1u);
  EXPECT_EQ(r.nonfinite_triangles, 1u);
  // The 4 good triangles are still a closed tetrahedron; vertex 5 is unused by them.
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.unused_vertices, 2u);
  EXPECT_NEAR(r.signed_volume, 1.0 / 6.0, 1e-15);
  EXPECT_EQ(r.bounds.max, Vec3(1, 1, 1));
  EXPECT_FALSE(r.is_clean());
  EXPECT_GE(r.defects().size(), 3u);
}

TEST(Validate, EmptyMesh) {
  const MeshReport r = validate(TriMesh{});
  EXPECT_EQ(r.triangles, 0u);
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.is_clean());
  ASSERT_FALSE(r.defects().empty());
  EXPECT_EQ(r.defects()[0], "no triangles");
}

TEST(Validate, VolumeAccurateFarFromOrigin) {
  TriMesh m = test::unit_cube();
  for (Vec3& p : m.positions) p += Vec3(1e3, -2e3, 1.1e3);
  const MeshReport r = validate(m);
  EXPECT_NEAR(r.signed_volume, 1.0, 1e-10);
  EXPECT_EQ(r.orientation, Orientation::kOutward);
  EXPECT_STREQ(orientation_name(r.orientation), "outward");
}

}  // namespace
}  // namespace trocar
