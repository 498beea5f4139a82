#include <gtest/gtest.h>

#include <limits>

#include "mesh_test_util.h"
#include "trocar/mesh/repair.h"
#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

/// The unit cube with every vertex split per face (a BodyParts3D-style crack mesh):
/// 24 vertices, 12 triangles, each face its own island.
TriMesh cracked_cube() {
  const TriMesh cube = test::unit_cube();
  TriMesh m;
  for (std::size_t f = 0; f < 6; ++f) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    std::uint32_t local[8];
    std::fill(std::begin(local), std::end(local), 99u);
    std::uint32_t next = 0;
    for (std::size_t t = 2 * f; t < 2 * f + 2; ++t) {
      Triangle out{};
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t v = cube.triangles[t][k];
        if (local[v] == 99u) {
          local[v] = next++;
          m.positions.push_back(cube.positions[v]);
        }
        out[k] = base + local[v];
      }
      m.triangles.push_back(out);
    }
  }
  return m;
}

TEST(Repair, CleanMeshIsUnchanged) {
  TriMesh m = test::tetrahedron();
  const RepairReport r = repair(m);
  EXPECT_FALSE(r.changed());
  EXPECT_TRUE(r.summary().empty());
  EXPECT_EQ(r.vertices_after, 4u);
  EXPECT_EQ(r.triangles_after, 4u);
  EXPECT_EQ(m.triangles, test::tetrahedron().triangles);
}

TEST(Repair, ExactMergeClosesCrackedCube) {
  TriMesh m = cracked_cube();
  ASSERT_EQ(m.positions.size(), 24u);
  const MeshReport before = validate(m);
  EXPECT_EQ(before.boundary_edges, 24u);
  EXPECT_EQ(before.duplicate_vertices, 16u);
  EXPECT_EQ(before.components, 6u);
  const RepairReport r = repair(m);
  EXPECT_EQ(r.vertices_merged, 16u);
  EXPECT_EQ(r.unused_vertices_removed, 16u);
  EXPECT_EQ(r.vertices_after, 8u);
  EXPECT_EQ(r.triangles_after, 12u);
  const MeshReport after = validate(m);
  EXPECT_TRUE(after.is_clean()) << ::testing::PrintToString(after.defects());
  EXPECT_NEAR(after.signed_volume, 1.0, 1e-15);
}

TEST(Repair, ToleranceMergeKeepsLowestIndexAndOrder) {
  TriMesh m = cracked_cube();
  for (std::size_t v = 0; v < m.positions.size(); ++v)  // jitter every copy by < 1e-9
    m.positions[v] += Vec3(1e-10 * static_cast<Real>(v % 5), 0, -3e-11 * static_cast<Real>(v % 3));
  const std::vector<Vec3> original = m.positions;
  RepairOptions exact;
  TriMesh m_exact = m;
  repair(m_exact, exact);
  EXPECT_FALSE(validate(m_exact).closed);  // jitter defeats the exact merge

  RepairOptions opts;
  opts.merge_tolerance_rel = 1e-9;  // × diagonal √3
  const RepairReport r = repair(m, opts);
  EXPECT_NEAR(r.merge_tolerance, 1e-9 * std::sqrt(3.0), 1e-17);  // the jitter grows the box a little
  EXPECT_EQ(r.vertices_merged, 16u);
  ASSERT_EQ(m.positions.size(), 8u);
  EXPECT_TRUE(validate(m).is_clean());
  // Survivors are the lowest-index copies, in their original order.
  std::size_t last = 0;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const auto it = std::find(original.begin(), original.end(), m.positions[i]);
    ASSERT_NE(it, original.end());
    const auto index = static_cast<std::size_t>(it - original.begin());
    if (i > 0) {
      EXPECT_GT(index, last);
    }
    last = index;
  }
}

TEST(Repair, VertexRepresentatives) {
  const std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(1 + 1e-7, 0, 0),
                               Vec3(std::numeric_limits<Real>::infinity(), 0, 0), Vec3(2, 0, 0)};
  const auto exact = vertex_representatives(p, 0);
  EXPECT_EQ(exact, (std::vector<std::uint32_t>{0, 1, 0, 3, 4, 5}));
  const auto near = vertex_representatives(p, 1e-6);
  EXPECT_EQ(near, (std::vector<std::uint32_t>{0, 1, 0, 1, 4, 5}));
  const auto coarse = vertex_representatives(p, 1.5);  // greedy: 5 is 2 from 0, the only rep
  EXPECT_EQ(coarse, (std::vector<std::uint32_t>{0, 0, 0, 0, 4, 5}));
}

TEST(Repair, InsideOutCubeIsFlipped) {
  TriMesh m = test::unit_cube();
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  const RepairReport r = repair(m);
  EXPECT_EQ(r.patches, 1u);
  EXPECT_EQ(r.patches_flipped_outward, 1u);
  EXPECT_EQ(r.triangles_flipped, 12u);
  EXPECT_EQ(m.triangles, test::unit_cube().triangles);
  EXPECT_NEAR(validate(m).signed_volume, 1.0, 1e-15);
}

TEST(Repair, OneFlippedTriangleIsFixed) {
  for (std::size_t bad : {0u, 5u, 11u}) {
    TriMesh m = test::unit_cube();
    std::swap(m.triangles[bad][1], m.triangles[bad][2]);
    const RepairReport r = repair(m);
    EXPECT_EQ(r.triangles_flipped, 1u) << bad;
    const MeshReport v = validate(m);
    EXPECT_EQ(v.inconsistent_edges, 0u);
    EXPECT_TRUE(v.is_clean()) << bad;
  }
}

TEST(Repair, TexcoordsFollowFlipsAndDrops) {
  TriMesh m = test::tetrahedron();
  m.triangles.push_back({1, 2, 0});  // duplicate of triangle 0 (dropped)
  std::swap(m.triangles[3][1], m.triangles[3][2]);  // flipped (repaired)
  for (std::size_t c = 0; c < 3 * m.triangles.size(); ++c) m.texcoords.emplace_back(static_cast<Real>(c), 0);
  m.normals.assign(4, Vec3::UnitZ());
  const RepairReport r = repair(m);
  EXPECT_EQ(r.duplicate_triangles_removed, 1u);
  EXPECT_EQ(r.triangles_flipped, 1u);
  ASSERT_EQ(m.texcoords.size(), 12u);
  EXPECT_EQ(m.normals.size(), 4u);
  // Triangle 3 was {1,3,2} with texcoords 9,10,11; flipped back to {1,2,3} → 9,11,10.
  EXPECT_EQ(m.triangles[3], (Triangle{1, 2, 3}));
  EXPECT_EQ(m.texcoords[9].x(), 9.0);
  EXPECT_EQ(m.texcoords[10].x(), 11.0);
  EXPECT_EQ(m.texcoords[11].x(), 10.0);
  EXPECT_TRUE(validate(m).is_clean());
}

TEST(Repair, DropsInvalidDegenerateDuplicateAndUnused) {
  TriMesh m = test::tetrahedron();
  m.positions.emplace_back(std::numeric_limits<Real>::quiet_NaN(), 0, 0);  // 4
  m.positions.emplace_back(0.5, 0, 0);                                     // 5, on edge 0–1
  m.positions.emplace_back(7, 7, 7);                                       // 6, unused
  m.normals.assign(7, Vec3::UnitX());
  m.normals[6] = Vec3::UnitY();
  m.triangles.push_back({0, 1, 42});  // out of range
  m.triangles.push_back({0, 4, 1});   // non-finite corner
  m.triangles.push_back({0, 5, 1});   // zero area
  m.triangles.push_back({3, 3, 1});   // repeated index
  m.triangles.push_back({3, 2, 1});   // duplicate of {1,2,3} (kept first)
  const RepairReport r = repair(m);
  EXPECT_EQ(r.invalid_triangles_removed, 2u);
  EXPECT_EQ(r.degenerate_removed, 2u);
  EXPECT_EQ(r.duplicate_triangles_removed, 1u);
  EXPECT_EQ(r.unused_vertices_removed, 3u);
  EXPECT_EQ(r.vertices_before, 7u);
  EXPECT_EQ(r.triangles_before, 9u);
  EXPECT_EQ(m.triangles, test::tetrahedron().triangles);
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.normals.size(), 4u);
  EXPECT_EQ(r.summary().size(), 4u);
  EXPECT_TRUE(validate(m).is_clean());
}

TEST(Repair, UnusedVertexRemapKeepsNormalsInStep) {
  TriMesh m = test::tetrahedron();
  m.positions.insert(m.positions.begin(), Vec3(5, 5, 5));  // unused vertex 0
  for (Triangle& t : m.triangles)
    for (auto& v : t) ++v;
  for (std::size_t v = 0; v < 5; ++v) m.normals.emplace_back(static_cast<Real>(v), 0, 0);
  const RepairReport r = repair(m);
  EXPECT_EQ(r.unused_vertices_removed, 1u);
  EXPECT_EQ(m.triangles, test::tetrahedron().triangles);
  for (std::size_t v = 0; v < 4; ++v) EXPECT_EQ(m.normals[v].x(), static_cast<Real>(v + 1));
}

TEST(Repair, SmallComponentsRemoved) {
  TriMesh m = test::unit_cube();
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  for (const Vec3& p : test::tetrahedron().positions) m.positions.push_back(p * 0.01 + Vec3(3, 0, 0));
  for (Triangle t : test::tetrahedron().triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  {
    TriMesh copy = m;
    RepairOptions opts;
    opts.min_component_triangles = 5;
    const RepairReport r = repair(copy, opts);
    EXPECT_EQ(r.components_removed, 1u);
    EXPECT_EQ(r.component_triangles_removed, 4u);
    EXPECT_EQ(copy.positions.size(), 8u);
  }
  {
    TriMesh copy = m;
    RepairOptions opts;
    opts.min_component_area_fraction = 0.01;  // the tetrahedron has ~4e−5 of the area
    const RepairReport r = repair(copy, opts);
    EXPECT_EQ(r.components_removed, 1u);
    EXPECT_TRUE(validate(copy).is_clean());
  }
  {
    TriMesh copy = m;
    const RepairReport r = repair(copy);
    EXPECT_EQ(r.components_removed, 0u);
    EXPECT_EQ(validate(copy).components, 2u);
  }
}

TEST(Repair, InsideOutPatchFlippedPerShell) {
  // Two separate cubes: one outward, one inside out. Each closed patch is oriented alone.
  TriMesh m = test::unit_cube();
  for (const Vec3& p : test::unit_cube().positions) m.positions.push_back(p + Vec3(3, 0, 0));
  for (Triangle t : test::unit_cube().triangles) m.triangles.push_back({t[0] + 8, t[2] + 8, t[1] + 8});
  EXPECT_NEAR(validate(m).signed_volume, 0.0, 1e-14);
  const RepairReport r = repair(m);
  EXPECT_EQ(r.patches, 2u);
  EXPECT_EQ(r.patches_flipped_outward, 1u);
  EXPECT_EQ(r.triangles_flipped, 12u);
  EXPECT_NEAR(validate(m).signed_volume, 2.0, 1e-14);
  EXPECT_TRUE(validate(m).is_clean());
}

TEST(Repair, OpenSurfaceWindingMadeConsistentButNotOriented) {
  TriMesh m = test::unit_cube();
  m.triangles.erase(m.triangles.begin() + 2, m.triangles.begin() + 4);
  std::swap(m.triangles[0][1], m.triangles[0][2]);  // flip the seed triangle itself
  const RepairReport r = repair(m);
  // The seed keeps its winding, so the other 9 triangles turn; the open box is then inside out.
  EXPECT_EQ(r.triangles_flipped, 9u);
  EXPECT_EQ(r.patches_flipped_outward, 0u);
  const MeshReport v = validate(m);
  EXPECT_EQ(v.inconsistent_edges, 0u);
  EXPECT_EQ(v.boundary_edges, 4u);
}

TEST(Repair, NonManifoldEdgeDoesNotPropagate) {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
  const RepairReport r = repair(m);
  EXPECT_EQ(r.patches, 3u);
  EXPECT_EQ(r.triangles_flipped, 0u);
}

TEST(Repair, StepsCanBeSwitchedOff) {
  TriMesh m = cracked_cube();
  RepairOptions opts;
  opts.merge_vertices = false;
  const RepairReport r = repair(m, opts);
  EXPECT_EQ(r.vertices_merged, 0u);
  EXPECT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(r.patches, 6u);
}

}  // namespace
}  // namespace trocar
