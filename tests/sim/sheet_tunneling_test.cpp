// The tunneling metric on an open tissue (sim/sheet_crossing.cpp): a capsule probe and a flat
// 60 × 60 mm sheet (z = 0, normals up, border held), three motions with hand-known outcomes.
#include <gtest/gtest.h>

#include <string>

#include "sheet_scene.h"
#include "trocar/mesh/generate.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/sheet_boundary.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

struct Counts {
  std::uint64_t tunneling = 0, contacts = 0;
};

Counts run(const std::string& text, int steps) {
  Scene scene = parse_scene(text, "probe-sheet.json", ".");
  Simulation sim(std::move(scene.world), scene.settings);
  Counts c;
  for (int n = 0; n < steps; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    EXPECT_TRUE(m.finite);
    c.tunneling += m.tunneling_events;
    c.contacts += m.contacts_applied;
    EXPECT_EQ(m.vertices_inside, 0u);  // a sheet has no inside: no penetration depth
  }
  return c;
}

TEST(SheetTunneling, FastProbeThroughSlowDetectorCounts) {
  // Down through the middle at 2 m/s with detection every 20 ms: the capsule (tip at the local
  // origin, shaft up) passes the sheet between two detections, so its lower vertices change
  // sides with no contact reported.
  const Counts c = run(test::sheet_scene("[0.001, 0.002, 0.02]", "[0.001, 0.002, -0.06]", 0.04, 0.02), 60);
  EXPECT_GT(c.tunneling, 0u);
}

TEST(SheetTunneling, SlowPressAnsweredByContactsCountsNone) {
  // Down 3 mm into the sheet at 0.1 m/s, detection every step: every touch gets a contact.
  const Counts c = run(test::sheet_scene("[0.001, 0.002, 0.005]", "[0.001, 0.002, -0.003]", 0.08, 0.001), 150);
  EXPECT_GT(c.contacts, 0u);
  EXPECT_EQ(c.tunneling, 0u);
}

TEST(SheetTunneling, StabThroughWithDetectionEveryStepGrowsWithSpeed) {
  // 80 mm straight through the middle, detection every step. The response cannot stop a
  // kinematic probe; whether a crossing vertex is seen depends on how far it moves per step
  // against the capsule's ~0.3–1 mm triangles near the tip. Measured: 0 events at 0.1 m/s,
  // 1 at 0.2, 2 at 0.5, 24 at 2 m/s (908 contacts).
  std::uint64_t last = 0;
  for (const double seconds : {0.8, 0.16, 0.04}) {  // 0.1, 0.5, 2 m/s
    const Counts c = run(test::sheet_scene("[0.001, 0.002, 0.02]", "[0.001, 0.002, -0.06]", seconds, 0.001),
                         static_cast<int>(seconds * 1000) + 20);
    EXPECT_GT(c.contacts, 0u) << seconds;
    if (seconds == 0.8) {
      EXPECT_EQ(c.tunneling, 0u);
    }
    EXPECT_GE(c.tunneling, last) << seconds;
    last = c.tunneling;
  }
  EXPECT_GT(last, 0u);
}

TEST(SheetTunneling, GoingAroundTheBorderCountsNone) {
  // From above the sheet to below it just outside its border (x = 0.0335: the capsule's 2 mm
  // radius leaves 1.5 mm to the edge at x = 0.03), with slow detection: the vertices change
  // sides of the sheet's plane, their closest feature is the border, and nothing crosses.
  const Counts c = run(test::sheet_scene("[0.0335, 0.0, 0.02]", "[0.0335, 0.0, -0.06]", 0.04, 0.02), 60);
  EXPECT_EQ(c.contacts, 0u);
  EXPECT_EQ(c.tunneling, 0u);
}

TEST(SheetBoundary, MarksTheBorderOfAGridSheet) {
  // A 4 × 3 cell sheet: 2·(4 + 3) = 14 border edges; (make_sheet's layout) vertex 0 is a corner.
  const TriMesh sheet = make_sheet(0.04, 0.03, 4, 3);
  const SheetBoundary border(sheet.positions, sheet.triangles);
  EXPECT_EQ(border.boundary_edge_count(), 14u);
  std::size_t faces = 0, border_vertices = 0;
  for (std::uint32_t t = 0; t < sheet.triangles.size(); ++t) {
    const Triangle& tri = sheet.triangles[t];
    faces += border.on_boundary(t, tri, TriangleFeature::kFace, 0) ? 1 : 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = sheet.positions[tri[static_cast<std::size_t>(k)]];
      const bool on_rim = p.x() <= -0.02 + 1e-12 || p.x() >= 0.02 - 1e-12 || p.y() <= -0.015 + 1e-12 ||
                          p.y() >= 0.015 - 1e-12;
      EXPECT_EQ(border.on_boundary(t, tri, TriangleFeature::kVertex, k), on_rim) << t << " " << k;
      border_vertices += on_rim ? 1 : 0;
    }
  }
  EXPECT_EQ(faces, 0u);
  EXPECT_GT(border_vertices, 0u);
  // A closed surface has no border.
  const TriMesh ball = make_icosphere(0.01, 1);
  EXPECT_EQ(SheetBoundary(ball.positions, ball.triangles).boundary_edge_count(), 0u);
}

}  // namespace
}  // namespace trocar
