// The three broad phases give identical contact sets after the narrow phase: random soups,
// moving generated and real meshes, adversarial cases.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_util.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

using test::expect_all_agree;
using test::Scene;

TEST(BroadPhaseEquivalence, RandomSoups) {
  std::mt19937 rng(12345);
  std::size_t total = 0;
  for (int trial = 0; trial < 12; ++trial) {
    Scene scene;
    const double size = trial % 3 == 0 ? 0.5 : (trial % 3 == 1 ? 0.1 : 0.02);
    scene.add(test::random_soup(rng, 150, Vec3::Zero(), 1.0, size), ObjectRole::kInstrument);
    scene.add(test::random_soup(rng, 300, Vec3(0.3, 0.2, 0.1), 1.0, size), ObjectRole::kTissue);
    if (trial % 2 == 0) scene.add(test::random_soup(rng, 100, Vec3(-0.3, 0.4, 0.2), 1.0, size), ObjectRole::kRigid);
    if (trial % 4 == 0) scene.add(test::random_soup(rng, 80, Vec3(0.1, 0.1, 0.1), 1.0, size), ObjectRole::kTissue);
    if (trial % 4 == 1) scene.add(test::random_soup(rng, 60, Vec3(0.2, 0.1, 0.3), 1.0, size), ObjectRole::kRigid);
    if (trial % 4 == 2) scene.add(test::random_soup(rng, 70, Vec3(0.0, 0.3, 0.0), 1.0, size), ObjectRole::kInstrument);
    const auto objects = scene.objects();
    total += expect_all_agree(objects, "soup " + std::to_string(trial)).size();
  }
  EXPECT_GT(total, 1000u);  // the soups do intersect
}

TEST(BroadPhaseEquivalence, SoupsWithSetCellSizes) {
  // Cell sizes from far below to far above the triangle size, including all-in-one-cell.
  std::mt19937 rng(99);
  Scene scene;
  scene.add(test::random_soup(rng, 200, Vec3(5, 5, 5), 1.0, 0.4), ObjectRole::kInstrument);
  scene.add(test::random_soup(rng, 300, Vec3(5.2, 5.0, 5.1), 1.0, 0.4), ObjectRole::kTissue);
  const auto objects = scene.objects();
  const auto reference = test::contacts_with(BroadPhaseKind::kBruteForce, objects);
  ASSERT_GT(reference.size(), 50u);
  for (const double h : {0.003, 0.05, 0.2, 1.0, 1000.0}) {
    OhcSettings settings;
    settings.cell_size = h;
    settings.max_pair_tests_per_primitive = 0;  // the cell hash, whose cell size this is about
    CollisionDetector ohc(settings);
    const auto found = ohc.detect(objects);
    test::expect_same_contacts(reference, {found.begin(), found.end()}, "cell " + std::to_string(h));
    test::expect_unique_candidates(ohc.candidates(), objects, "cell " + std::to_string(h));
    if (h == 1000.0) {
      EXPECT_EQ(ohc.ohc_stats()->cells_touched, 1u);  // every primitive in cell (0, 0, 0)
      EXPECT_EQ(ohc.ohc_stats()->potential_cells, 1u);
    }
  }
}

TEST(BroadPhaseEquivalence, MovingGeneratedMeshes) {
  // A deforming sphere (tissue) cut by a moving capsule (instrument), a second tissue and a
  // rigid box touching them: every contact kind but instrument–instrument.
  test::CuttingScene cut(make_icosphere(0.05, 3), make_capsule(0.004, 0.04, 12, 4), 0.006, 0.01);
  cut.scene.add(test::translated(make_icosphere(0.02, 2), Vec3(0.06, 0, 0)), ObjectRole::kTissue);
  cut.scene.add(test::translated(make_box(0.04, 0.04, 0.04), Vec3(0.0, 0.0, -0.06)), ObjectRole::kRigid);
  CollisionDetector ohc(BroadPhaseKind::kOhc);
  CollisionDetector bvh(BroadPhaseKind::kBvh);
  CollisionDetector brute(BroadPhaseKind::kBruteForce);
  std::size_t with_contact = 0;
  for (int frame = 0; frame < 10; ++frame) {
    cut.set_frame(frame);
    const auto objects = cut.scene.objects();
    const auto a = ohc.detect(objects);
    const auto b = bvh.detect(objects);
    const auto c = brute.detect(objects);
    const std::string what = "frame " + std::to_string(frame);
    test::expect_same_contacts({c.begin(), c.end()}, {a.begin(), a.end()}, what + " ohc");
    test::expect_same_contacts({c.begin(), c.end()}, {b.begin(), b.end()}, what + " bvh");
    with_contact += a.empty() ? 0 : 1;
  }
  EXPECT_EQ(with_contact, 10u);
}

struct SharedCase {
  const char* tissue;
  double tissue_scale;
  const char* tool;
  double depth;  // metres
};

TEST(BroadPhaseEquivalence, MovingSharedMeshes) {
  // Units: the lapgym STLs are in millimetres, the SOFA liver is ~6.4 units across (scaled to
  // ~0.1 m). The tool's lowest point is pushed a few millimetres into the tissue's top.
  const SharedCase cases[] = {
      {"liver_sofa_smooth.obj", 0.015, "grasper_jaw_maryland_left_lapgym.stl", 0.004},
      {"liver_sofa_smooth.obj", 0.015, "probe_hook_electrode_lapgym.stl", 0.004},
      {"gallbladder_lapgym.stl", 0.001, "grasper_jaw_maryland_left_lapgym.stl", 0.003},
      {"gallbladder_lapgym.stl", 0.001, "probe_hook_electrode_lapgym.stl", 0.003},
  };
  for (const SharedCase& sc : cases) {
    auto tissue = test::shared_mesh(sc.tissue, sc.tissue_scale);
    auto tool = test::shared_mesh(sc.tool, 0.001);
    if (!tissue || !tool) GTEST_SKIP() << test::shared_absent("the tissue or tool mesh");
    test::CuttingScene cut(std::move(*tissue), std::move(*tool), sc.depth, 0.003);
    CollisionDetector ohc(BroadPhaseKind::kOhc);
    CollisionDetector bvh(BroadPhaseKind::kBvh);
    std::size_t contacts = 0;
    for (int frame = 0; frame < 6; ++frame) {
      cut.set_frame(frame);
      const auto objects = cut.scene.objects();
      const std::string what = std::string(sc.tissue) + " vs " + sc.tool + " frame " + std::to_string(frame);
      const auto a = ohc.detect(objects);
      const auto b = bvh.detect(objects);
      test::expect_same_contacts({b.begin(), b.end()}, {a.begin(), a.end()}, what + " ohc vs bvh");
      test::expect_unique_candidates(ohc.candidates(), objects, what);
      contacts += a.size();
      // Brute force once on the liver pairs (4–7 million tests each); the gallbladder pairs
      // (14–24 million) rely on BVH, itself checked against brute force everywhere else.
      if (frame == 0 && std::string(sc.tissue).starts_with("liver")) {
        const auto c = test::contacts_with(BroadPhaseKind::kBruteForce, objects);
        test::expect_same_contacts(c, {a.begin(), a.end()}, what + " ohc vs brute");
      }
    }
    EXPECT_GT(contacts, 6u * 5u) << sc.tissue << " vs " << sc.tool << ": the tool should cut in";
  }
}

// --- adversarial cases -----------------------------------------------------------------------

TriMesh one_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  TriMesh m;
  m.positions = {a, b, c};
  m.triangles = {{0, 1, 2}};
  return m;
}

TEST(BroadPhaseAdversarial, CoplanarOverlap) {
  Scene scene;
  scene.add(one_triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)), ObjectRole::kInstrument);
  scene.add(one_triangle(Vec3(0.2, 0.2, 0), Vec3(1.2, 0.2, 0), Vec3(0.2, 1.2, 0)), ObjectRole::kTissue);
  const auto objects = scene.objects();
  const auto contacts = expect_all_agree(objects, "coplanar");
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_TRUE(contacts[0].coplanar);
}

TEST(BroadPhaseAdversarial, EdgeEdgeTouching) {
  // B's edge passes through the midpoint of A's edge (0,0,0)–(1,0,0); otherwise they are apart.
  Scene scene;
  scene.add(one_triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)), ObjectRole::kInstrument);
  scene.add(one_triangle(Vec3(0.5, -0.5, 0.5), Vec3(0.5, 0.5, -0.5), Vec3(0.5, -1, -1)), ObjectRole::kTissue);
  const auto objects = scene.objects();
  for (const double h : {0.0, 0.5, 0.25, 1e-3}) {  // the touching point on cell boundaries, too
    OhcSettings settings;
    settings.cell_size = h;
    CollisionDetector ohc(settings);
    const auto found = ohc.detect(objects);
    ASSERT_EQ(found.size(), 1u) << "cell " << h;
    EXPECT_LT((found[0].segment_p - Vec3(0.5, 0, 0)).norm(), 1e-12);
    EXPECT_LT((found[0].segment_q - Vec3(0.5, 0, 0)).norm(), 1e-12);
  }
  EXPECT_EQ(expect_all_agree(objects, "edge-edge").size(), 1u);
}

TEST(BroadPhaseAdversarial, TinyTriangleInHugeCell) {
  // A 1 µm triangle inside a 1 m triangle's cell, and 200 more tiny ones, with the automatic
  // cell size (dominated by the tiny ones: the big triangle forces the cell-doubling budget)
  // and with a set 10 m cell.
  std::mt19937 rng(7);
  Scene scene;
  TriMesh tiny = test::random_soup(rng, 200, Vec3(0.1, 0.1, -0.001), 0.5, 2e-6);
  TriMesh hit = one_triangle(Vec3(0.3, 0.3, -1e-6), Vec3(0.3 + 1e-6, 0.3, 1e-6), Vec3(0.3, 0.3 + 1e-6, 1e-6));
  const auto base = static_cast<std::uint32_t>(tiny.positions.size());
  for (const Vec3& p : hit.positions) tiny.positions.push_back(p);
  tiny.triangles.push_back({base, base + 1, base + 2});
  scene.add(std::move(tiny), ObjectRole::kInstrument);
  scene.add(one_triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)), ObjectRole::kTissue);
  const auto objects = scene.objects();
  const auto contacts = expect_all_agree(objects, "tiny in huge");
  ASSERT_GE(contacts.size(), 1u);
  EXPECT_EQ(contacts.back().triangle_a, 200u);
  OhcSettings settings;
  settings.cell_size = 10.0;
  settings.max_pair_tests_per_primitive = 0;  // the cell hash
  CollisionDetector ohc(settings);
  EXPECT_EQ(ohc.detect(objects).size(), contacts.size());
  // The budget kept the entries linear in the primitives.
  settings.cell_size = 0;
  CollisionDetector auto_ohc(settings);
  auto_ohc.detect(objects);
  const OhcStats& stats = *auto_ohc.ohc_stats();
  EXPECT_LE(static_cast<double>(stats.entries), 64.0 * stats.primitives_hashed + 64.0);
}

TEST(BroadPhaseAdversarial, HugeTrianglesAcrossTheClampedGrid) {
  // Two crossing triangles 2e12 across with 1 m cells: their cell ranges are clamped to ±2^30, so
  // a range spans 2^31 + 1 cells (past int32), and the budget doubles the cell many times.
  Scene scene;
  scene.add(one_triangle(Vec3(-1e12, -1e12, 0), Vec3(1e12, -1e12, 0), Vec3(0, 1e12, 0)), ObjectRole::kInstrument);
  scene.add(one_triangle(Vec3(0, 0, -1e12), Vec3(1e12, 0, 1e12), Vec3(-1e12, 0, 1e12)), ObjectRole::kTissue);
  const auto objects = scene.objects();
  const auto reference = test::contacts_with(BroadPhaseKind::kBruteForce, objects);
  ASSERT_EQ(reference.size(), 1u);
  OhcSettings settings;
  settings.cell_size = 1.0;
  settings.max_pair_tests_per_primitive = 0;  // the cell hash, whose cells this is about
  CollisionDetector ohc(settings);
  const auto found = ohc.detect(objects);
  test::expect_same_contacts(reference, {found.begin(), found.end()}, "huge");
  EXPECT_GT(ohc.ohc_stats()->cell_size, 1e6);
  CollisionDetector by_cluster_pairs;  // the default: one cluster pair, no cells
  const auto direct = by_cluster_pairs.detect(objects);
  test::expect_same_contacts(reference, {direct.begin(), direct.end()}, "huge (cluster pairs)");
  EXPECT_TRUE(by_cluster_pairs.ohc_stats()->cluster_pair_path);
}

TEST(BroadPhaseAdversarial, ObjectsFarApart) {
  Scene scene;
  scene.add(make_icosphere(1.0, 2), ObjectRole::kInstrument);
  scene.add(test::translated(make_icosphere(1.0, 2), Vec3(1e6, 0, 0)), ObjectRole::kTissue);
  scene.add(test::translated(make_icosphere(1.0, 2), Vec3(0, -1e9, 0)), ObjectRole::kTissue);
  const auto objects = scene.objects();
  EXPECT_TRUE(expect_all_agree(objects, "far apart").empty());
  CollisionDetector ohc;
  ohc.detect(objects);
  EXPECT_EQ(ohc.ohc_stats()->objects_overlapping, 0u);
  EXPECT_EQ(ohc.ohc_stats()->primitives_hashed, 0u);
  EXPECT_TRUE(ohc.candidates().empty());
}

TEST(BroadPhaseAdversarial, EmptyMeshesAndNoObjects) {
  Scene scene;
  scene.add(TriMesh{}, ObjectRole::kInstrument);
  scene.add(make_icosphere(1.0, 1), ObjectRole::kTissue);
  TriMesh points_only;
  points_only.positions = {Vec3(0, 0, 0), Vec3(1, 1, 1)};
  scene.add(points_only, ObjectRole::kInstrument);
  const auto objects = scene.objects();
  EXPECT_TRUE(expect_all_agree(objects, "empty").empty());
  for (const BroadPhaseKind kind : {BroadPhaseKind::kOhc, BroadPhaseKind::kBvh, BroadPhaseKind::kBruteForce}) {
    CollisionDetector d(kind);
    EXPECT_TRUE(d.detect(std::span<const CollisionObject>{}).empty());
    EXPECT_TRUE(d.detect(std::span<const CollisionObject>(objects.data() + 1, 1)).empty());
  }
}

TEST(BroadPhaseAdversarial, RigidRigidNotTestedSameObjectNeverPaired) {
  Scene scene;
  scene.add(make_icosphere(1.0, 1), ObjectRole::kRigid);
  scene.add(make_icosphere(1.0, 1), ObjectRole::kRigid);  // identical: would intersect everywhere
  const auto objects = scene.objects();
  EXPECT_TRUE(expect_all_agree(objects, "rigid-rigid").empty());
}

TEST(BroadPhaseAdversarial, ManyClusterPairsTakeTheSweep) {
  // Two copies of a 5,120-triangle sphere: 160 clusters on each side, 160 × 160 pairs of them
  // to consider (over the 1,024 the cascade tests one by one), so it sorts and sweeps them.
  Scene scene;
  scene.add(make_icosphere(1.0, 4), ObjectRole::kInstrument);
  scene.add(make_icosphere(1.0, 4), ObjectRole::kTissue);
  const auto objects = scene.objects();
  const auto contacts = expect_all_agree(objects, "identical L4", false);
  EXPECT_GE(contacts.size(), 5120u * 4u);
  CollisionDetector ohc;
  ohc.detect(objects);
  EXPECT_GT(ohc.ohc_stats()->cluster_pairs, 500u);
}

TEST(BroadPhaseAdversarial, IdenticalOverlappingMeshes) {
  // Two copies of one mesh: every triangle touches itself and its neighbours (shared vertices
  // and edges, coplanar pairs), the worst case for tolerances.
  Scene scene;
  scene.add(make_icosphere(1.0, 2), ObjectRole::kInstrument);
  scene.add(make_icosphere(1.0, 2), ObjectRole::kTissue);
  const auto objects = scene.objects();
  const auto contacts = expect_all_agree(objects, "identical");
  EXPECT_GE(contacts.size(), 320u * 4u);  // itself + 3 edge neighbours at least
}

}  // namespace
}  // namespace trocar
