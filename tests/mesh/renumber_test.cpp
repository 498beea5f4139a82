// Vertex renumbering for locality (mesh/renumber.h): the same surface under new vertex names, and
// edges that join nearby indices.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <random>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/renumber.h"
#include "trocar/mesh/topology.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

/// Largest and mean |i − j| over the mesh's unique edges.
struct Span {
  std::uint32_t largest = 0;
  double mean = 0;
};
Span edge_span(const TriMesh& mesh) {
  const MeshTopology topology(mesh);
  Span s;
  for (const Edge& e : topology.edges()) {
    s.largest = std::max(s.largest, e.v1 - e.v0);
    s.mean += e.v1 - e.v0;
  }
  s.mean /= static_cast<double>(topology.edge_count());
  return s;
}

/// The mesh under a random renaming of its vertices.
TriMesh shuffled(const TriMesh& mesh, unsigned seed) {
  std::vector<std::uint32_t> order(mesh.vertex_count());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  return renumber_vertices(mesh, order);
}

TEST(Renumber, KeepsEveryTriangleCornerNormalAndTexcoord) {
  TriMesh mesh = make_icosphere(1.0, 2);
  mesh.normals = mesh.positions;  // unit normals of the unit sphere
  for (std::size_t c = 0; c < 3 * mesh.triangle_count(); ++c)
    mesh.texcoords.emplace_back(0.001 * static_cast<Real>(c), 0.5);
  const TriMesh scrambled = shuffled(mesh, 7);
  const std::vector<std::uint32_t> order = locality_vertex_order(scrambled);
  const TriMesh out = renumber_vertices(scrambled, order);
  ASSERT_EQ(out.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(out.triangle_count(), mesh.triangle_count());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = out.triangles[t][k], w = scrambled.triangles[t][k];
      ASSERT_EQ(order[v], w);  // vertex v is old vertex order[v]
      ASSERT_EQ(out.positions[v], scrambled.positions[w]);
      ASSERT_EQ(out.normals[v], scrambled.normals[w]);
    }
  EXPECT_EQ(out.texcoords, mesh.texcoords);  // per corner: unchanged
  // The same triangles, corners and order: area and volume to the bit.
  EXPECT_EQ(out.area(), mesh.area());
  EXPECT_EQ(out.signed_volume(), mesh.signed_volume());
}

// A strip of 50 quads (51 × 2 vertices, each quad two triangles) under random names: a
// breadth-first order from one end takes the vertices about two by two along the strip, so no
// edge joins indices more than 3 apart (a vertex's neighbours are its partner and the next pair).
TEST(Renumber, StripComesOutInOrderAlongIt) {
  const TriMesh strip = shuffled(make_sheet(1.0, 0.02, 50, 1), 3);
  ASSERT_EQ(strip.vertex_count(), 102u);
  EXPECT_GT(edge_span(strip).largest, 50u);
  const TriMesh out = renumber_vertices(strip, locality_vertex_order(strip));
  EXPECT_LE(edge_span(out).largest, 3u);
}

// Two triangles apart and a vertex no triangle uses, worked by hand: component {0, 2, 5} first
// (its lowest vertex is 0; a pass from 0 reaches 5 last, so it starts at 5; neighbours of equal
// degree by index: 0, 2), then {1, 3, 4} from 4, then the unused 6.
TEST(Renumber, ComponentsByLowestVertexThenUnusedVertices) {
  TriMesh mesh;
  for (int k = 0; k < 7; ++k) mesh.positions.emplace_back(k, 0, 0);
  mesh.triangles = {{0, 5, 2}, {4, 1, 3}};
  EXPECT_EQ(locality_vertex_order(mesh), (std::vector<std::uint32_t>{5, 0, 2, 4, 1, 3, 6}));
  EXPECT_EQ(inverse_order(std::vector<std::uint32_t>{5, 0, 2, 4, 1, 3, 6}),
            (std::vector<std::uint32_t>{1, 4, 2, 5, 3, 0, 6}));
}

TEST(Renumber, RejectsAnOrderThatIsNotAPermutation) {
  const TriMesh mesh = make_icosphere(1.0, 0);  // 12 vertices
  std::vector<std::uint32_t> order(12);
  std::iota(order.begin(), order.end(), 0u);
  order[7] = 3;  // 3 twice, 7 never
  EXPECT_THROW(renumber_vertices(mesh, order), Error);
  order.pop_back();
  EXPECT_THROW(renumber_vertices(mesh, order), Error);
  order = std::vector<std::uint32_t>(12, 0);
  std::iota(order.begin(), order.end(), 1u);  // 12 is out of range
  EXPECT_THROW(renumber_vertices(mesh, order), Error);
  TriMesh broken = mesh;
  broken.triangles[3][1] = 12;  // no such vertex
  EXPECT_THROW(locality_vertex_order(broken), Error);
  // An empty mesh has an empty order.
  EXPECT_TRUE(locality_vertex_order(TriMesh{}).empty());
  EXPECT_EQ(renumber_vertices(TriMesh{}, {}).vertex_count(), 0u);
}

// The shared liver (2,194 V): in the file's order an edge joins vertices 779 indices apart on
// average (largest 2,193); renumbered, 45.6 (largest 98).
TEST(Renumber, SharedLiverEdgesJoinNearbyVertices) {
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.obj");
  const TriMesh liver = load_mesh(path);
  const Span before = edge_span(liver);
  const Span after = edge_span(renumber_vertices(liver, locality_vertex_order(liver)));
  EXPECT_GT(before.mean, 500);
  EXPECT_LT(after.mean, 60);
  EXPECT_LT(after.largest, 150u);
}

}  // namespace
}  // namespace trocar
