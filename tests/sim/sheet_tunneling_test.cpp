// The penetration and tunneling metrics on an open tissue (sim/sheet_crossing.cpp): a capsule
// probe and a flat 60 × 60 mm sheet (z = 0, normals up, border held), motions with hand-known
// outcomes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "sheet_scene.h"
#include "trocar/mesh/generate.h"
#include "trocar/scene/scene.h"
#include "trocar/mesh/sheet_boundary.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

struct Counts {
  std::uint64_t tunneling = 0, contacts = 0;
  Real penetration_max = 0;       ///< deepest vertex through the sheet over the run (m)
  Real final_penetration = 0;     ///< at the last step (m)
  std::uint32_t final_through = 0;  ///< vertices through the sheet at the last step
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
    c.penetration_max = std::max(c.penetration_max, m.penetration_max);
    c.final_penetration = m.penetration_max;
    c.final_through = m.vertices_inside;
  }
  return c;
}

TEST(SheetTunneling, FastProbeThroughSlowDetectorCounts) {
  // Down through the middle at 2 m/s with detection every 20 ms: the capsule (tip at the local
  // origin, shaft up) passes the sheet between two detections, so its lower vertices change
  // sides with no contact reported.
  const Counts c = run(test::sheet_scene("[0.001, 0.002, 0.02]", "[0.001, 0.002, -0.06]", 0.04, 0.02), 60);
  EXPECT_GT(c.tunneling, 0u);
  EXPECT_GT(c.final_through, 0u);  // and its vertices are through the sheet, at depth
  EXPECT_GT(c.final_penetration, 0.004);
}

TEST(SheetPenetration, DepthBelowAnUnpushedSheetByHand) {
  // Response off (K = 0): the sheet stays flat at z = 0 (no gravity, nothing pushes it). The
  // probe's origin goes from 20 mm above to 10 mm below at 0.1 m/s with detection every step,
  // so its tip vertex (2 mm below the origin) ends 12 mm through the sheet: penetration 12 mm.
  // Every crossing had a contact (no rule (a) event); the vertices that end deeper than the
  // probe's 4 mm thickness are rule (b) events, one each.
  const Counts c =
      run(test::sheet_scene("[0.001, 0.002, 0.02]", "[0.001, 0.002, -0.01]", 0.3, 0.001, 0.0), 320);
  EXPECT_NEAR(c.final_penetration, 0.012, 1e-9);
  EXPECT_NEAR(c.penetration_max, 0.012, 1e-9);
  EXPECT_GT(c.final_through, 0u);
  EXPECT_GT(c.tunneling, 0u);
  // Down and back up to 20 mm above: every vertex crosses back, none is through at the end.
  const Counts back =
      run(test::sheet_scene("[0.001, 0.002, 0.02]", "[0.001, 0.002, -0.01]", 0.3, 0.001, 0.0, 0.3), 620);
  EXPECT_NEAR(back.penetration_max, 0.012, 1e-9);
  EXPECT_EQ(back.final_through, 0u);
  EXPECT_EQ(back.final_penetration, 0.0);
}

TEST(SheetTunneling, SlowPressAnsweredByContactsCountsNone) {
  // Down 3 mm into the sheet at 0.1 m/s, detection every step: every touch gets a contact.
  const Counts c = run(test::sheet_scene("[0.001, 0.002, 0.005]", "[0.001, 0.002, -0.003]", 0.08, 0.001), 150);
  EXPECT_GT(c.contacts, 0u);
  EXPECT_EQ(c.tunneling, 0u);
  std::printf("[ slow press ] through %u, final depth %.3g mm, max %.3g mm\n", c.final_through,
              c.final_penetration * 1e3, c.penetration_max * 1e3);
}

TEST(SheetTunneling, StabThroughWithDetectionEveryStepGrowsWithSpeed) {
  // 80 mm straight through the middle, detection every step. The response cannot stop a
  // kinematic probe. Slowly, the sheet wraps the probe and is dragged down with it; fast, the
  // probe leaves it behind. Either way vertices end through the sheet deeper than the probe's
  // 4 mm thickness (rule (b) events), and whether a crossing vertex is seen depends on how far it
  // moves per step against the capsule's ~0.3–1 mm triangles near the tip (rule (a), which grows
  // with speed). Measured: 37 / 79 / 134 events, 37 / 37 / 73 of the 74 vertices through at the
  // end, 13 / 9.8 / 62 mm deep, at 0.1 / 0.5 / 2 m/s (rule (a) alone, before sheets had depth:
  // 0 / 2 / 24).
  constexpr std::uint32_t kVertices = 74;
  std::uint64_t last = 0;
  for (const double seconds : {0.8, 0.16, 0.04}) {  // 0.1, 0.5, 2 m/s
    const Counts c = run(test::sheet_scene("[0.001, 0.002, 0.02]", "[0.001, 0.002, -0.06]", seconds, 0.001),
                         static_cast<int>(seconds * 1000) + 20);
    EXPECT_GT(c.contacts, 0u) << seconds;
    EXPECT_GT(c.final_through, 0u) << seconds;
    EXPECT_LE(c.final_through, kVertices) << seconds;
    EXPECT_GT(c.final_penetration, 0.004) << seconds;
    EXPECT_GT(c.tunneling, 0u) << seconds;
    EXPECT_GE(c.tunneling, last) << seconds;
    last = c.tunneling;
  }
  EXPECT_GT(last, 100u);
}

TEST(SheetTunneling, GoingAroundTheBorderCountsNone) {
  // From above the sheet to below it just outside its border (x = 0.0335: the capsule's 2 mm
  // radius leaves 1.5 mm to the edge at x = 0.03), with slow detection: the vertices change
  // sides of the sheet's plane, their closest feature is the border, and nothing crosses.
  const Counts c = run(test::sheet_scene("[0.0335, 0.0, 0.02]", "[0.0335, 0.0, -0.06]", 0.04, 0.02), 60);
  EXPECT_EQ(c.contacts, 0u);
  EXPECT_EQ(c.tunneling, 0u);
  EXPECT_EQ(c.penetration_max, 0.0);  // never through: its side was lost at the border
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
