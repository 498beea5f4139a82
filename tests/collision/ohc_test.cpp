// OHC specifics: cell classification counted by hand on a built scene, contact kinds and
// ordering, determinism, statistics and the table growing only when needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "scene_util.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

using test::Scene;

// Three small triangles that fit inside one unit cell [cx, cx+1] × [cy, cy+1] × [0, 1] and
// pairwise intersect (planes z = ½, y = ½ and x = ½ through the cell's centre).
TriMesh cell_triangle(int kind, int cx, int cy) {
  const Vec3 o(cx, cy, 0);
  TriMesh m;
  if (kind == 0) m.positions = {o + Vec3(0.2, 0.2, 0.5), o + Vec3(0.8, 0.2, 0.5), o + Vec3(0.5, 0.8, 0.5)};
  if (kind == 1) m.positions = {o + Vec3(0.2, 0.5, 0.2), o + Vec3(0.8, 0.5, 0.2), o + Vec3(0.5, 0.5, 0.8)};
  if (kind == 2) m.positions = {o + Vec3(0.5, 0.2, 0.2), o + Vec3(0.5, 0.8, 0.2), o + Vec3(0.5, 0.5, 0.8)};
  m.triangles = {{0, 1, 2}};
  return m;
}

TriMesh merge(const TriMesh& a, const TriMesh& b) {
  TriMesh m = a;
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  for (const Vec3& p : b.positions) m.positions.push_back(p);
  for (const Triangle& t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return m;
}

// Object 0 (instrument): kind-0 triangles in cells (0,0,0) and (2,0,0).
// Object 1 (tissue):     kind-1 triangles in cells (0,0,0), (1,0,0) and (2,1,0).
// Object 2 (rigid):      kind-2 triangles in cells (0,0,0) and (2,0,0).
Scene hand_scene() {
  Scene s;
  s.add(merge(cell_triangle(0, 0, 0), cell_triangle(0, 2, 0)), ObjectRole::kInstrument);
  s.add(merge(merge(cell_triangle(1, 0, 0), cell_triangle(1, 1, 0)), cell_triangle(1, 2, 1)), ObjectRole::kTissue);
  s.add(merge(cell_triangle(2, 0, 0), cell_triangle(2, 2, 0)), ObjectRole::kRigid);
  return s;
}

TEST(OhcCells, HandBuiltSceneClassification) {
  const Scene scene = hand_scene();
  const auto objects = scene.objects();
  OhcSettings settings;
  settings.cell_size = 1.0;
  settings.cascade = false;  // hash every triangle: the counts below are by hand
  OhcBroadPhase ohc(settings);
  std::vector<CandidatePair> pairs;
  ohc.find_pairs(objects, pairs);
  const OhcStats& s = ohc.stats();
  // All three object boxes overlap pairwise (x ∈ [0.2, 2.8] for all, y overlaps in [0.2, 0.8]).
  EXPECT_EQ(s.objects_overlapping, 3u);
  EXPECT_EQ(s.primitives_hashed, 7u);
  EXPECT_EQ(s.entries, 7u);  // each triangle inside one cell
  // Touched: (0,0,0) objects {0,1,2} potential; (2,0,0) {0,2} potential; (1,0,0) {1} solo;
  // (2,1,0) {1} solo. Block spanned: x 0..2, y 0..1, z 0..0 = 6 cells, 2 of them empty.
  EXPECT_EQ(s.cells_touched, 4u);
  EXPECT_EQ(s.potential_cells, 2u);
  EXPECT_EQ(s.solo_cells, 2u);
  EXPECT_EQ(s.empty_cells, 2u);
  // Pairs: cell (0,0,0) gives 0–1, 0–2, 1–2; cell (2,0,0) gives 0–2.
  EXPECT_EQ(s.candidate_pairs, 4u);
  EXPECT_EQ(pairs.size(), 4u);
  EXPECT_EQ(s.cell_size, 1.0);
  EXPECT_GE(s.table_size, 2 * s.entries);
  EXPECT_EQ(s.table_size & (s.table_size - 1), 0u);  // power of two

  // With the cascade only the overlap regions are hashed: the tissue's triangle in (2,1,0)
  // (y ∈ [1.2, 1.8]) lies outside every overlap and is dropped, the rest stay.
  settings.cascade = true;
  settings.cluster_cascade = false;  // the object level alone (see ClusterCascade below)
  ohc.set_settings(settings);
  ohc.find_pairs(objects, pairs);
  EXPECT_EQ(ohc.stats().primitives_hashed, 6u);
  EXPECT_EQ(ohc.stats().potential_cells, 2u);
  EXPECT_EQ(ohc.stats().candidate_pairs, 4u);
}

// Tissue: 32 kind-1 triangles in cell (0,0,0) and 32 in (5,5,0): two clusters (Morton order).
// Instrument: kind-0 triangles in (0,0,0) and (5,0,0): one cluster spanning both.
TEST(OhcCells, ClusterCascadeHandBuilt) {
  TriMesh tissue;
  for (int k = 0; k < 32; ++k) tissue = merge(tissue, cell_triangle(1, 0, 0));
  for (int k = 0; k < 32; ++k) tissue = merge(tissue, cell_triangle(1, 5, 5));
  Scene scene;
  scene.add(merge(cell_triangle(0, 0, 0), cell_triangle(0, 5, 0)), ObjectRole::kInstrument);
  scene.add(tissue, ObjectRole::kTissue);
  const auto objects = scene.objects();
  OhcSettings settings;
  settings.cell_size = 1.0;
  settings.cascade = true;
  settings.cluster_cascade = false;
  OhcBroadPhase ohc(settings);
  std::vector<CandidatePair> pairs;
  ohc.find_pairs(objects, pairs);
  // Object level: boxes overlap in x [0.2, 5.8], y [0.5, 0.8], z 0.5. The tissue cluster in
  // (5,5,0) (y = 5.5) stays closed; the other 32 tissue triangles and both instrument triangles
  // are hashed: (0,0,0) holds 33 (potential), (5,0,0) the instrument's second one (solo);
  // block x 0..5 = 6 cells, 4 empty. Pairs: the 32 tissue triangles with the instrument's first.
  EXPECT_EQ(ohc.stats().objects_overlapping, 1u);
  EXPECT_EQ(ohc.stats().cluster_pairs, 0u);
  EXPECT_EQ(ohc.stats().clusters_opened, 2u);
  EXPECT_EQ(ohc.stats().primitives_hashed, 34u);
  EXPECT_EQ(ohc.stats().entries, 34u);
  EXPECT_EQ(ohc.stats().cells_touched, 2u);
  EXPECT_EQ(ohc.stats().potential_cells, 1u);
  EXPECT_EQ(ohc.stats().solo_cells, 1u);
  EXPECT_EQ(ohc.stats().empty_cells, 4u);
  EXPECT_EQ(ohc.stats().candidate_pairs, 32u);
  const auto keys = [](const std::vector<CandidatePair>& v) {
    std::vector<std::array<std::uint32_t, 4>> k;
    for (const CandidatePair& p : v) k.push_back({p.object_a, p.object_b, p.triangle_a, p.triangle_b});
    std::sort(k.begin(), k.end());
    return k;
  };
  const auto object_level = keys(pairs);

  // Cluster level: the instrument's cluster meets only the tissue cluster in (0,0,0); their
  // overlap is x [0.2, 0.8], y 0.5, z 0.5, which the instrument's triangle in (5,0,0) misses.
  // 33 triangles hashed, all into (0,0,0); the same 32 pairs.
  settings.cluster_cascade = true;
  settings.max_pair_tests_per_primitive = 0;  // the cell hash
  ohc.set_settings(settings);
  ohc.find_pairs(objects, pairs);
  EXPECT_FALSE(ohc.stats().cluster_pair_path);
  EXPECT_EQ(ohc.stats().cluster_pairs, 1u);
  EXPECT_EQ(ohc.stats().clusters_opened, 2u);
  EXPECT_EQ(ohc.stats().primitives_hashed, 33u);
  EXPECT_EQ(ohc.stats().entries, 33u);
  EXPECT_EQ(ohc.stats().cells_touched, 1u);
  EXPECT_EQ(ohc.stats().potential_cells, 1u);
  EXPECT_EQ(ohc.stats().solo_cells, 0u);
  EXPECT_EQ(ohc.stats().empty_cells, 0u);
  EXPECT_EQ(ohc.stats().candidate_pairs, 32u);
  EXPECT_EQ(keys(pairs), object_level);

  // The cluster-pair path (the default): the one cluster pair's 1 × 32 box tests, no cells; the
  // same 33 triangles opened and the same 32 pairs.
  settings.max_pair_tests_per_primitive = OhcSettings{}.max_pair_tests_per_primitive;
  ohc.set_settings(settings);
  ohc.find_pairs(objects, pairs);
  EXPECT_TRUE(ohc.stats().cluster_pair_path);
  EXPECT_EQ(ohc.stats().cluster_pairs, 1u);
  EXPECT_EQ(ohc.stats().primitives_hashed, 33u);
  EXPECT_EQ(ohc.stats().entries, 0u);
  EXPECT_EQ(ohc.stats().cells_touched, 0u);
  EXPECT_EQ(ohc.stats().candidate_pairs, 32u);
  EXPECT_EQ(keys(pairs), object_level);
}

TEST(OhcCells, ContactKindsAndOrder) {
  const Scene scene = hand_scene();
  const auto objects = scene.objects();
  CollisionDetector detector;
  const auto contacts = detector.detect(objects);
  ASSERT_EQ(contacts.size(), 4u);
  const std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t> expected[] = {
      {0, 1, 0, 0}, {0, 2, 0, 0}, {0, 2, 1, 1}, {1, 2, 0, 0}};
  const ContactKind kinds[] = {ContactKind::kInstrumentTissue, ContactKind::kInstrumentRigid,
                               ContactKind::kInstrumentRigid, ContactKind::kTissueRigid};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(contact_key(contacts[k]), expected[k]) << k;
    EXPECT_EQ(contacts[k].kind, kinds[k]) << k;
    EXPECT_FALSE(contacts[k].coplanar);
  }
  // The segment of 0–1 in cell (0,0,0): planes z = ½ and y = ½ meet on x ∈ [0.35, 0.65].
  EXPECT_NEAR(std::min(contacts[0].segment_p.x(), contacts[0].segment_q.x()), 0.35, 1e-12);
  EXPECT_NEAR(std::max(contacts[0].segment_p.x(), contacts[0].segment_q.x()), 0.65, 1e-12);
  EXPECT_NEAR(contacts[0].segment_p.y(), 0.5, 1e-12);
  EXPECT_NEAR(contacts[0].segment_p.z(), 0.5, 1e-12);

  // Reversed indices: rigid 0, tissue 1, instrument 2. The instrument still comes first.
  Scene reversed;
  for (int i = 2; i >= 0; --i) reversed.add(scene.meshes[i], scene.roles[i]);
  const auto robjects = reversed.objects();
  const auto rc = detector.detect(robjects);
  ASSERT_EQ(rc.size(), 4u);
  const std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t> rexpected[] = {
      {1, 0, 0, 0}, {2, 0, 0, 0}, {2, 0, 1, 1}, {2, 1, 0, 0}};
  const ContactKind rkinds[] = {ContactKind::kTissueRigid, ContactKind::kInstrumentRigid,
                                ContactKind::kInstrumentRigid, ContactKind::kInstrumentTissue};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(contact_key(rc[k]), rexpected[k]) << k;
    EXPECT_EQ(rc[k].kind, rkinds[k]) << k;
  }
}

TEST(OhcCells, SameRolesLowerIndexFirstAndKindNames) {
  Scene s;
  s.add(cell_triangle(0, 0, 0), ObjectRole::kTissue);
  s.add(cell_triangle(1, 0, 0), ObjectRole::kTissue);
  s.add(cell_triangle(2, 0, 0), ObjectRole::kInstrument);
  s.add(cell_triangle(0, 0, 0), ObjectRole::kInstrument);
  const auto objects = s.objects();
  CollisionDetector d;
  const auto c = d.detect(objects);
  // Pairs: 0–1 tissue–tissue; 2–0, 2–1, 3–0, 3–1 instrument–tissue; 2–3 instrument–instrument.
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(contact_key(c[0]), std::make_tuple(0u, 1u, 0u, 0u));
  EXPECT_EQ(c[0].kind, ContactKind::kTissueTissue);
  EXPECT_EQ(contact_key(c[1]), std::make_tuple(2u, 0u, 0u, 0u));
  EXPECT_EQ(contact_key(c[3]), std::make_tuple(2u, 3u, 0u, 0u));
  EXPECT_EQ(c[3].kind, ContactKind::kInstrumentInstrument);
  EXPECT_EQ(contact_key(c[4]), std::make_tuple(3u, 0u, 0u, 0u));
  EXPECT_TRUE(c[4].coplanar);  // two identical triangles
  EXPECT_STREQ(contact_kind_name(ContactKind::kTissueRigid), "tissue-rigid");
  EXPECT_STREQ(role_name(ObjectRole::kInstrument), "instrument");
  EXPECT_STREQ(broad_phase_name(BroadPhaseKind::kOhc), "ohc");
}

TEST(OhcCells, DeterministicAcrossRunsAndDetectors) {
  test::CuttingScene cut(make_icosphere(0.05, 3), make_capsule(0.004, 0.04, 12, 4), 0.006, 0.01);
  CollisionDetector a;
  std::vector<std::vector<Contact>> first;
  for (int f = 0; f < 5; ++f) {
    cut.set_frame(f);
    const auto objects = cut.scene.objects();
    const auto c = a.detect(objects);
    first.emplace_back(c.begin(), c.end());
  }
  CollisionDetector b;  // a fresh detector, same frames
  for (int f = 0; f < 5; ++f) {
    cut.set_frame(f);
    const auto objects = cut.scene.objects();
    std::vector<Contact> out;
    b.detect(objects, out);
    test::expect_same_contacts(first[static_cast<std::size_t>(f)], out, "frame " + std::to_string(f));
    EXPECT_TRUE(std::is_sorted(out.begin(), out.end(), contact_less));
    EXPECT_FALSE(out.empty());
  }
}

TEST(OhcCells, ACutKeepsTheClusterOrderAndFindsWhatAFreshDetectorFinds) {
  // A cut removes triangles of the tissue (object 1): remap_object hands the OHC the mapping, and
  // its clusters take the old order without the removed ones instead of sorting again. The
  // contacts must be a fresh detector's, frame after frame.
  test::CuttingScene cut(make_icosphere(0.05, 3), make_capsule(0.004, 0.04, 12, 4), 0.006, 0.01);
  CollisionDetector a;
  cut.set_frame(0);
  a.detect(cut.scene.objects());  // the clusters of the uncut tissue
  std::vector<Triangle> kept;
  std::vector<std::uint32_t> origin;
  const std::vector<Triangle>& before = cut.scene.meshes[1].triangles;
  for (std::uint32_t t = 0; t < before.size(); ++t)
    if (t % 7 != 3) {
      kept.push_back(before[t]);
      origin.push_back(t);
    }
  ASSERT_LT(kept.size(), before.size());
  a.broad_phase().remap_object(1, origin);
  cut.scene.meshes[1].triangles = kept;  // a new buffer: the OHC sees another object
  std::size_t found = 0;
  for (int f = 1; f < 5; ++f) {
    cut.set_frame(f);
    const auto objects = cut.scene.objects();
    const auto remapped = a.detect(objects);
    std::vector<Contact> first(remapped.begin(), remapped.end());
    CollisionDetector fresh;
    std::vector<Contact> out;
    fresh.detect(objects, out);
    test::expect_same_contacts(out, first, "frame " + std::to_string(f));
    found += first.size();
  }
  EXPECT_GT(found, 0u);
  // A mapping that is not one-to-one is refused (the next build sorts anew), and still correct.
  std::vector<std::uint32_t> twice(cut.scene.meshes[1].triangles.size(), 0);
  a.broad_phase().remap_object(1, twice);
  cut.scene.meshes[1].triangles.pop_back();
  const auto objects = cut.scene.objects();
  const auto after = a.detect(objects);
  std::vector<Contact> out;
  CollisionDetector fresh;
  fresh.detect(objects, out);
  test::expect_same_contacts(out, std::vector<Contact>(after.begin(), after.end()), "after a refused remap");
}

TEST(OhcCells, TableSizedByTheFrame) {
  test::CuttingScene cut(make_icosphere(0.05, 3), make_capsule(0.004, 0.04, 12, 4), 0.006, 0.01);
  OhcSettings settings;
  settings.max_pair_tests_per_primitive = 0;  // the cell hash, whose table this is about
  OhcBroadPhase ohc(settings);
  std::vector<CandidatePair> pairs;
  for (int f = 0; f < 5; ++f) {
    cut.set_frame(f);
    ohc.find_pairs(cut.scene.objects(), pairs);
    // The smallest power of two ≥ 2·entries (at least 16): a frame after a bigger one does not
    // pay for the bigger table (its buffer is kept, see allocation_test.cpp).
    const std::uint64_t table = ohc.stats().table_size;
    EXPECT_GE(table, 2 * ohc.stats().entries);
    EXPECT_TRUE(table == 16 || table / 2 < 2 * ohc.stats().entries) << table;
    EXPECT_EQ(table & (table - 1), 0u);
    EXPECT_GT(ohc.stats().potential_cells, 0u);
    EXPECT_EQ(ohc.stats().cells_touched, ohc.stats().solo_cells + ohc.stats().potential_cells);
    EXPECT_GT(ohc.stats().cell_size, 0.0);
  }
  // Far apart: nothing hashed.
  Scene far;
  far.add(make_icosphere(1.0, 1), ObjectRole::kInstrument);
  far.add(test::translated(make_icosphere(1.0, 1), Vec3(10, 0, 0)), ObjectRole::kTissue);
  ohc.find_pairs(far.objects(), pairs);
  EXPECT_EQ(ohc.stats().entries, 0u);
  EXPECT_TRUE(pairs.empty());
}

TEST(OhcCells, CascadeHashesOnlyTheOverlap) {
  // A 20K-triangle sphere touched at one pole by a small capsule: only a few percent of the
  // sphere's triangles may be hashed.
  test::CuttingScene cut(make_icosphere(0.05, 5), make_capsule(0.002, 0.03, 12, 4), 0.002);
  CollisionDetector d;
  const auto c = d.detect(cut.scene.objects());
  EXPECT_FALSE(c.empty());
  const OhcStats& s = *d.ohc_stats();
  EXPECT_LT(s.primitives_hashed, 20480u / 50u) << "the cascade should drop almost everything";
  EXPECT_GE(s.candidate_pairs, c.size());
}

}  // namespace
}  // namespace trocar
