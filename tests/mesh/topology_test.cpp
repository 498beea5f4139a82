#include <gtest/gtest.h>

#include <algorithm>

#include "mesh_test_util.h"
#include "trocar/core/error.h"
#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

TEST(MeshTopology, Tetrahedron) {
  const TriMesh m = test::tetrahedron();
  const MeshTopology topo(m);
  EXPECT_EQ(topo.vertex_count(), 4u);
  EXPECT_EQ(topo.triangle_count(), 4u);
  EXPECT_EQ(topo.edge_count(), 6u);
  EXPECT_EQ(topo.euler_characteristic(), 2);
  EXPECT_TRUE(topo.boundary_edges().empty());
  EXPECT_TRUE(topo.nonmanifold_edges().empty());
  EXPECT_TRUE(topo.nonmanifold_vertices().empty());
  EXPECT_EQ(topo.component_count(), 1u);
  // Edges sorted by (v0, v1): 01 02 03 12 13 23.
  const Edge expected[6] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (std::size_t e = 0; e < 6; ++e) {
    EXPECT_EQ(topo.edge(e), expected[e]);
    EXPECT_EQ(topo.edge_valence(e), 2u);
  }
  // Edge 01 is used by triangles 0 {0,2,1} and 1 {0,1,3}; wings are 2 and 3.
  const auto t01 = topo.edge_triangles(0);
  ASSERT_EQ(t01.size(), 2u);
  EXPECT_EQ(t01[0], 0u);
  EXPECT_EQ(t01[1], 1u);
  EXPECT_EQ(topo.opposite_vertices(0), (std::array<std::uint32_t, 2>{2, 3}));
  // Triangle 1 = {0,1,3}: local edges 01, 13, 30 → ids 0, 4, 2.
  EXPECT_EQ(topo.triangle_edges(1), (std::array<std::uint32_t, 3>{0, 4, 2}));
  EXPECT_TRUE(topo.traverses_forward(m, 1, 0));   // 0 → 1
  EXPECT_FALSE(topo.traverses_forward(m, 0, 0));  // 1 → 0 in {0,2,1}
  for (std::size_t v = 0; v < 4; ++v) EXPECT_EQ(topo.vertex_triangles(v).size(), 3u);
  const auto vt3 = topo.vertex_triangles(3);
  EXPECT_TRUE(std::is_sorted(vt3.begin(), vt3.end()));
  EXPECT_EQ(vt3[0], 1u);
}

TEST(MeshTopology, CubeWithOneFaceRemovedHasFourBoundaryEdges) {
  TriMesh m = test::unit_cube();
  m.triangles.erase(m.triangles.begin() + 2, m.triangles.begin() + 4);  // the +z face
  const MeshTopology topo(m);
  EXPECT_EQ(topo.edge_count(), 17u);  // the face's diagonal is gone
  ASSERT_EQ(topo.boundary_edges().size(), 4u);
  for (std::uint32_t e : topo.boundary_edges()) {
    const Edge& edge = topo.edge(e);
    EXPECT_GE(edge.v0, 4u);  // all on the top face (vertices 4..7)
    EXPECT_EQ(topo.opposite_vertices(e)[0], MeshTopology::kNone);
  }
  EXPECT_EQ(topo.euler_characteristic(), 1);  // a disc
}

TEST(MeshTopology, BowTieIsOneComponentWithANonManifoldVertex) {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};
  const MeshTopology topo(m);
  EXPECT_EQ(topo.component_count(), 1u);  // connected through vertex 0
  ASSERT_EQ(topo.nonmanifold_vertices().size(), 1u);
  EXPECT_EQ(topo.nonmanifold_vertices()[0], 0u);
  EXPECT_EQ(topo.boundary_edges().size(), 6u);
  EXPECT_TRUE(topo.nonmanifold_edges().empty());
}

TEST(MeshTopology, ThreeTrianglesOnOneEdgeAreNonManifold) {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshTopology topo(m);
  ASSERT_EQ(topo.nonmanifold_edges().size(), 1u);
  EXPECT_EQ(topo.edge(topo.nonmanifold_edges()[0]), (Edge{0, 1}));
  EXPECT_EQ(topo.edge_valence(topo.nonmanifold_edges()[0]), 3u);
  EXPECT_EQ(topo.opposite_vertices(topo.nonmanifold_edges()[0])[0], MeshTopology::kNone);
  EXPECT_EQ(topo.boundary_edges().size(), 6u);
  EXPECT_TRUE(topo.nonmanifold_vertices().empty());  // all three share the edge: one fan each
}

TEST(MeshTopology, ComponentsAndUnusedVertices) {
  TriMesh m = test::tetrahedron();
  TriMesh cube = test::unit_cube();
  const auto offset = static_cast<std::uint32_t>(m.positions.size() + 1);  // one unused vertex between
  m.positions.emplace_back(9, 9, 9);
  for (const Vec3& p : cube.positions) m.positions.push_back(p + Vec3(5, 0, 0));
  for (Triangle t : cube.triangles) m.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const MeshTopology topo(m);
  EXPECT_EQ(topo.vertex_count(), 13u);
  EXPECT_EQ(topo.used_vertex_count(), 12u);
  EXPECT_TRUE(topo.vertex_triangles(4).empty());
  ASSERT_EQ(topo.component_count(), 2u);
  EXPECT_EQ(topo.component_triangle_counts()[0], 4u);
  EXPECT_EQ(topo.component_triangle_counts()[1], 12u);
  EXPECT_EQ(topo.triangle_component(0), 0u);
  EXPECT_EQ(topo.triangle_component(15), 1u);
  EXPECT_EQ(topo.euler_characteristic(), 4);  // two spheres
}

TEST(MeshTopology, RepeatedIndexGetsNoEdge) {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  m.triangles = {{0, 0, 1}};
  const MeshTopology topo(m);
  EXPECT_EQ(topo.edge_count(), 1u);
  EXPECT_EQ(topo.triangle_edges(0)[0], MeshTopology::kNone);
  EXPECT_EQ(topo.vertex_triangles(0).size(), 1u);  // listed once
}

TEST(MeshTopology, OutOfRangeIndexThrows) {
  TriMesh m = test::tetrahedron();
  m.triangles[2][1] = 4;
  EXPECT_THROW(MeshTopology{m}, Error);
}

TEST(MeshTopology, Empty) {
  const MeshTopology topo{TriMesh{}};
  EXPECT_EQ(topo.edge_count(), 0u);
  EXPECT_EQ(topo.component_count(), 0u);
  EXPECT_EQ(topo.euler_characteristic(), 0);
}

}  // namespace
}  // namespace trocar
