// The swept reference check: a fast vertex through a triangle that both discrete frames miss,
// a slow approach that they do not, edge–edge crossings, and the cubic's roots.
#include <gtest/gtest.h>

#include <vector>

#include "trocar/collision/detector.h"
#include "trocar/collision/swept_check.h"
#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

std::vector<Vec3> moved(const std::vector<Vec3>& p, const Vec3& d) {
  std::vector<Vec3> out = p;
  for (Vec3& x : out) x += d;
  return out;
}

// Discrete contacts between an instrument and a tissue at one frame.
std::size_t discrete_contacts(const std::vector<Vec3>& tool, const std::vector<Triangle>& tool_tris,
                              const std::vector<Vec3>& tissue, const std::vector<Triangle>& tissue_tris) {
  const CollisionObject objects[] = {{ObjectRole::kInstrument, tool, tool_tris},
                                     {ObjectRole::kTissue, tissue, tissue_tris}};
  CollisionDetector d;
  return d.detect(objects).size();
}

TEST(SweptCheck, FastVertexThroughTriangleIsMissedByDiscreteTest) {
  // Tissue: one big triangle in z = 0. Tool: a small tetrahedron (1 mm) that jumps from 5 mm
  // above to 5 mm below within one step, passing through the triangle's interior.
  const std::vector<Vec3> tissue = {Vec3(-0.05, -0.05, 0), Vec3(0.05, -0.05, 0), Vec3(0, 0.05, 0)};
  const std::vector<Triangle> tissue_tris = {{0, 1, 2}};
  const TriMesh tet = [] {
    TriMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(0.001, 0, 0.001), Vec3(0, 0.001, 0.001), Vec3(-0.001, -0.001, 0.001)};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
  }();
  const auto start = moved(tet.positions, Vec3(0, 0, 0.005));
  const auto end = moved(tet.positions, Vec3(0, 0, -0.006));
  ASSERT_EQ(discrete_contacts(start, tet.triangles, tissue, tissue_tris), 0u);
  ASSERT_EQ(discrete_contacts(end, tet.triangles, tissue, tissue_tris), 0u);
  const SweptCheckResult r = swept_check({start, end, tet.triangles}, {tissue, tissue, tissue_tris});
  EXPECT_EQ(r.vertex_triangle_events, 4u);  // every tool vertex passes through the triangle
  EXPECT_EQ(r.missed_vertex_triangle, 4u);
  EXPECT_EQ(r.edge_edge_events, 0u);        // no tool edge meets a tissue edge
  EXPECT_EQ(r.missed(), 4u);
  EXPECT_GE(r.triangle_pairs_tested, 4u);
}

TEST(SweptCheck, SlowApproachMissesNothing) {
  // A tessellated tissue sheet and a capsule tip approaching slowly: first stopping short,
  // then pressing 0.5 mm in by the end frame (which the discrete test at that frame sees).
  const TriMesh sheet = make_sheet(0.1, 0.1, 20, 20);
  TriMesh tool = make_capsule(0.004, 0.03, 12, 4);  // tip at z = −0.004
  const auto above = moved(tool.positions, Vec3(0.0012, 0.0007, 0.0060));
  const auto closer = moved(tool.positions, Vec3(0.0012, 0.0007, 0.0050));
  const auto pressed = moved(tool.positions, Vec3(0.0012, 0.0007, 0.0035));
  const SweptCheckResult apart = swept_check({above, closer, tool.triangles}, {sheet.positions, sheet.positions, sheet.triangles});
  EXPECT_EQ(apart.events(), 0u);
  EXPECT_EQ(apart.missed(), 0u);
  ASSERT_GT(discrete_contacts(pressed, tool.triangles, sheet.positions, sheet.triangles), 0u);
  const SweptCheckResult in = swept_check({closer, pressed, tool.triangles}, {sheet.positions, sheet.positions, sheet.triangles});
  EXPECT_GT(in.events(), 0u);  // features do cross during the step ...
  EXPECT_EQ(in.missed(), 0u);  // ... but the end frame sees every one of them
}

TEST(SweptCheck, FastToolThroughTessellatedSheetMissesMany) {
  // The same capsule crossing the whole sheet in one step: vertex and edge crossings, all missed.
  const TriMesh sheet = make_sheet(0.1, 0.1, 20, 20);
  TriMesh tool = make_capsule(0.004, 0.01, 12, 4);
  const auto start = moved(tool.positions, Vec3(0.0012, 0.0007, 0.006));
  const auto end = moved(tool.positions, Vec3(0.0012, 0.0007, -0.02));
  ASSERT_EQ(discrete_contacts(start, tool.triangles, sheet.positions, sheet.triangles), 0u);
  ASSERT_EQ(discrete_contacts(end, tool.triangles, sheet.positions, sheet.triangles), 0u);
  const SweptCheckResult r = swept_check({start, end, tool.triangles}, {sheet.positions, sheet.positions, sheet.triangles});
  // Every tool vertex once, plus the sheet vertices inside the capsule's footprint (through the
  // bottom and the top of the capsule).
  EXPECT_GE(r.vertex_triangle_events, tool.positions.size());
  EXPECT_GT(r.edge_edge_events, 0u);
  EXPECT_EQ(r.missed(), r.events());
}

TEST(SweptCheck, EdgeEdgeCrossing) {
  // Two long thin triangles whose edges cross like scissors: the tool edge along x sweeps down
  // through the tissue edge along y; no vertex crosses a triangle.
  const std::vector<Vec3> tissue = {Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(-0.1, 0, -0.5)};
  const std::vector<Triangle> tt = {{0, 1, 2}};
  const std::vector<Vec3> tool0 = {Vec3(-1, 0, 0.1), Vec3(1, 0, 0.1), Vec3(0.0, 0.1, 0.6)};
  const std::vector<Triangle> it = {{0, 1, 2}};
  const auto tool1 = moved(tool0, Vec3(0, 0, -0.2));
  ASSERT_EQ(discrete_contacts(tool0, it, tissue, tt), 0u);
  const SweptCheckResult r = swept_check({tool0, tool1, it}, {tissue, tissue, tt});
  EXPECT_EQ(r.edge_edge_events, 1u);
  EXPECT_EQ(r.vertex_triangle_events, 0u);
}

TEST(SweptCheck, CoplanarityCubicRoots) {
  // x3 moves along z through the plane z = 0 of x0..x2 at t = 0.25.
  Real roots[3];
  const Vec3 z = Vec3::Zero();
  int n = coplanarity_times(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 1), z, z, z,
                            Vec3(0, 0, -4), roots);
  ASSERT_EQ(n, 1);
  EXPECT_NEAR(roots[0], 0.25, 1e-14);
  // A triangle rotating about x while the point sits still: sin-like cubic with 3 roots.
  // Plane through x0 = 0 with x1 = (1,0,0) and x2(t) = (0, 1 − 2t, 0) + (0,0,?)... use a point
  // oscillating: x3(t) = (0.3, 0.3, (t − 0.2)(t − 0.5)(t − 0.9)) is not linear; instead check a
  // cubic with the exact roots 0.2 and 0.8 from two moving points.
  n = coplanarity_times(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, -0.2), Vec3(0.3, 0.3, 0.8), z, z,
                        Vec3(0, 0, 1), Vec3(0, 0, -1), roots);
  // f(t) = x1 × x2(t) · x3(t) = (0, −z2, 1)·(0.3, 0.3, z3) = −0.3 z2 + z3 with z2 = −0.2 + t,
  // z3 = 0.8 − t: f = 0.06 − 0.3t + 0.8 − t → root t = 0.86/1.3.
  ASSERT_EQ(n, 1);
  EXPECT_NEAR(roots[0], 0.86 / 1.3, 1e-14);
  // No root in [0, 1].
  EXPECT_EQ(coplanarity_times(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 1), z, z, z,
                              Vec3(0, 0, -0.5), roots),
            0);
}

TEST(SweptCheck, RejectsMismatchedFrames) {
  const std::vector<Vec3> a = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::vector<Vec3> b = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  const std::vector<Triangle> t = {{0, 1, 2}};
  EXPECT_THROW(swept_check({a, b, t}, {a, a, t}), Error);
  EXPECT_EQ(swept_check({a, a, {}}, {a, a, t}).events(), 0u);
}

}  // namespace
}  // namespace trocar
