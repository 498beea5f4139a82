// remove_triangles: the cut model's triangles, vertices (compaction, bow-tie splits), masses and
// springs, checked against hand-computed numbers on a 4 × 4 grid, a sphere and a seeded soak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/topology.h"
#include "trocar/tissue/cut.h"
#include "trocar/tissue/settings.h"

namespace trocar {
namespace {

// The hand grid: 4 × 4 square cells of 1 cm, vertex (i, j) = 5j + i at (i, j) cm, each cell split
// along the same diagonal v00–v11 into triangles 2c = (v00, v10, v11) and 2c + 1 = (v00, v11,
// v01), c = 4j + i. Every triangle has area 0.5 cm² = 5e-5 m². With density 1000 kg/m³ and a
// 2 mm sheet, a triangle weighs 1000 × 5e-5 × 0.002 = 1e-4 kg, each corner holds 1e-4/3 kg of
// it, an interior vertex (six triangles) 2e-4 kg, the sheet 32 × 1e-4 = 3.2e-3 kg.
constexpr Real kCell = 0.01;
constexpr Real kTriangleMass = 1e-4;

std::uint32_t grid_vertex(std::uint32_t i, std::uint32_t j) { return 5 * j + i; }
std::uint32_t grid_triangle(std::uint32_t i, std::uint32_t j, std::uint32_t half) { return 2 * (4 * j + i) + half; }

TriMesh grid_mesh() {
  TriMesh mesh;
  for (std::uint32_t j = 0; j <= 4; ++j)
    for (std::uint32_t i = 0; i <= 4; ++i) mesh.positions.emplace_back(kCell * i, kCell * j, 0.0);
  for (std::uint32_t j = 0; j < 4; ++j)
    for (std::uint32_t i = 0; i < 4; ++i) {
      const std::uint32_t v00 = grid_vertex(i, j), v10 = v00 + 1, v01 = v00 + 5, v11 = v01 + 1;
      mesh.triangles.push_back({v00, v10, v11});
      mesh.triangles.push_back({v00, v11, v01});
    }
  return mesh;
}

MassSpringMaterial sheet_material() {
  MassSpringMaterial m;
  m.mass = 0;
  m.density = 1000;
  m.sheet_thickness = 0.002;
  m.k_structural = 300;
  m.k_bending = 30;
  m.spring_damping = 0.05;
  return m;
}

MassSpringSettings grid_settings() { return MassSpringSettings::build(grid_mesh(), sheet_material()); }

TriMesh mesh_of(const MassSpringSettings& s) {
  TriMesh mesh;
  mesh.positions = s.rest_positions;
  mesh.triangles = s.triangles;
  return mesh;
}

CutTopology cut(const MassSpringSettings& s, std::vector<std::uint32_t> removed) {
  return remove_triangles(s, std::span<const std::uint32_t>(removed));
}

bool has_spring(const MassSpringSettings& s, std::uint32_t a, std::uint32_t b, bool structural) {
  const std::size_t begin = structural ? 0 : s.structural_count;
  const std::size_t end = structural ? s.structural_count : s.springs.size();
  for (std::size_t k = begin; k < end; ++k)
    if (std::minmax(s.springs[k].i, s.springs[k].j) == std::minmax(a, b)) return true;
  return false;
}

void expect_identical(const MassSpringSettings& a, const MassSpringSettings& b) {
  ASSERT_EQ(a.springs.size(), b.springs.size());
  for (std::size_t k = 0; k < a.springs.size(); ++k) {
    EXPECT_EQ(a.springs[k].i, b.springs[k].i) << k;
    EXPECT_EQ(a.springs[k].j, b.springs[k].j) << k;
    EXPECT_EQ(a.springs[k].rest_length, b.springs[k].rest_length) << k;
    EXPECT_EQ(a.springs[k].stiffness, b.springs[k].stiffness) << k;
    EXPECT_EQ(a.springs[k].damping, b.springs[k].damping) << k;
  }
  EXPECT_EQ(a.structural_count, b.structural_count);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.rest_areas, b.rest_areas);
  EXPECT_EQ(a.mean_rest_area, b.mean_rest_area);
  EXPECT_EQ(a.closed, b.closed);
  EXPECT_EQ(a.rest_volume, b.rest_volume);
  EXPECT_EQ(a.rest_positions, b.rest_positions);
  EXPECT_EQ(a.home_positions, b.home_positions);
  EXPECT_EQ(a.masses, b.masses);
  EXPECT_EQ(a.inverse_masses, b.inverse_masses);
  EXPECT_EQ(a.fixed, b.fixed);
  EXPECT_EQ(a.k_area, b.k_area);
  EXPECT_EQ(a.k_volume, b.k_volume);
  EXPECT_EQ(a.k_home, b.k_home);
  EXPECT_EQ(a.home_yield, b.home_yield);
  EXPECT_EQ(a.damping, b.damping);
  EXPECT_EQ(a.gravity, b.gravity);
}

std::vector<std::uint32_t> iota_vector(std::size_t n) {
  std::vector<std::uint32_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint32_t>(i);
  return v;
}

TEST(CutTopology, NothingRemovedIsTheSameModel) {
  MassSpringMaterial mat = sheet_material();
  mat.k_area = 5;
  mat.k_volume = 7;
  mat.k_home = 3;
  mat.home_yield = 0.004;
  mat.damping = 0.8;
  FixedSelection fixed;
  fixed.indices = {0, 3};
  const Vec3 g(0, 0, -9.81);
  const MassSpringSettings sphere = MassSpringSettings::build(make_icosphere(0.05, 2), mat, fixed, g);
  const MassSpringSettings sheet = MassSpringSettings::build(make_sheet(0.2, 0.1, 6, 4, 0.01), mat, fixed, g);
  for (const MassSpringSettings* s : {&sphere, &sheet}) {
    for (const std::vector<std::uint32_t>& removed :
         {std::vector<std::uint32_t>{}, std::vector<std::uint32_t>{100000, 100000, 0xffffffffu}}) {
      const CutTopology c = cut(*s, removed);
      expect_identical(c.settings, *s);
      EXPECT_EQ(c.vertex_origin, iota_vector(s->vertex_count()));
      EXPECT_EQ(c.triangle_origin, iota_vector(s->triangles.size()));
      EXPECT_EQ(c.spring_origin, iota_vector(s->springs.size()));
    }
  }
  EXPECT_TRUE(sphere.closed);
  EXPECT_EQ(sheet.fixed[3], 1);
}

// The general path against build() on the smaller mesh: where no vertex is dropped or split the
// cut must give build()'s springs bit for bit, in its order (and its masses up to rounding).
TEST(CutTopology, MatchesBuildOfTheCutMesh) {
  struct Case {
    TriMesh mesh;
    std::vector<std::uint32_t> removed;
    Real k_bending;
  };
  const std::vector<Case> cases = {
      {grid_mesh(), {grid_triangle(1, 1, 0)}, 30},
      {grid_mesh(), {grid_triangle(2, 2, 1), grid_triangle(1, 2, 0), grid_triangle(2, 2, 1)}, 0},
      {make_icosphere(0.05, 2), {7}, 30},
      {make_sheet(0.2, 0.1, 6, 4, 0.01), {33, 14}, 30},  // cells (4, 2) and (1, 1): interior
  };
  for (std::size_t n = 0; n < cases.size(); ++n) {
    MassSpringMaterial mat = sheet_material();
    mat.k_bending = cases[n].k_bending;
    const MassSpringSettings s = MassSpringSettings::build(cases[n].mesh, mat);
    TriMesh smaller = cases[n].mesh;
    std::vector<Triangle> kept;
    for (std::size_t t = 0; t < smaller.triangles.size(); ++t)
      if (std::find(cases[n].removed.begin(), cases[n].removed.end(), t) == cases[n].removed.end())
        kept.push_back(smaller.triangles[t]);
    smaller.triangles = kept;
    MassSpringMaterial by_area = mat;  // same mass per area as the original
    by_area.mass = 0;
    const MassSpringSettings want = MassSpringSettings::build(smaller, by_area);
    const CutTopology got = cut(s, cases[n].removed);
    ASSERT_EQ(got.settings.vertex_count(), s.vertex_count()) << n;  // nothing dropped or split
    ASSERT_EQ(got.settings.springs.size(), want.springs.size()) << n;
    EXPECT_EQ(got.settings.structural_count, want.structural_count) << n;
    for (std::size_t k = 0; k < want.springs.size(); ++k) {
      EXPECT_EQ(got.settings.springs[k].i, want.springs[k].i) << n << " " << k;
      EXPECT_EQ(got.settings.springs[k].j, want.springs[k].j) << n << " " << k;
      EXPECT_EQ(got.settings.springs[k].rest_length, want.springs[k].rest_length) << n << " " << k;
      EXPECT_EQ(got.settings.springs[k].stiffness, want.springs[k].stiffness) << n << " " << k;
    }
    EXPECT_EQ(got.settings.triangles, want.triangles) << n;
    EXPECT_EQ(got.settings.rest_areas, want.rest_areas) << n;
    if (!s.closed) {  // an open sheet: the same density × thickness per area, so the same masses
      for (std::size_t v = 0; v < want.vertex_count(); ++v)
        EXPECT_NEAR(got.settings.masses[v], want.masses[v], 1e-12 * want.masses[v]) << n << " " << v;
    }
    EXPECT_EQ(got.settings.mean_rest_area, s.mean_rest_area) << n;  // kept, not want's
    EXPECT_FALSE(got.settings.closed);
  }
}

TEST(CutTopology, OneInteriorTriangleOfAGrid) {
  const MassSpringSettings s = grid_settings();
  ASSERT_EQ(s.triangles.size(), 32u);
  ASSERT_EQ(s.structural_count, 56u);          // 20 rows + 20 columns + 16 diagonals
  ASSERT_EQ(s.springs.size(), 56u + 40u);      // 56 − 16 boundary edges are interior
  EXPECT_NEAR(s.total_mass(), 32 * kTriangleMass, 1e-15);
  const std::uint32_t a = grid_vertex(1, 1), b = grid_vertex(2, 1), c = grid_vertex(2, 2);  // 6, 7, 12
  const std::uint32_t t = grid_triangle(1, 1, 0);
  ASSERT_EQ(s.triangles[t], (Triangle{a, b, c}));
  for (std::uint32_t v : {a, b, c}) EXPECT_NEAR(s.masses[v], 6 * kTriangleMass / 3, 1e-16);

  const CutTopology r = cut(s, {t});
  const MassSpringSettings& m = r.settings;
  EXPECT_EQ(m.triangles.size(), 31u);
  EXPECT_EQ(r.triangle_origin.size(), 31u);
  EXPECT_EQ(r.triangle_origin[t], t + 1);  // the ones after it move down by one
  EXPECT_EQ(r.triangle_origin[t - 1], t - 1);
  EXPECT_EQ(m.vertex_count(), 25u);  // nothing dropped, nothing split
  EXPECT_EQ(r.vertex_origin, iota_vector(25));

  // The three edges stay (their other triangle still uses them), with their rest lengths.
  EXPECT_EQ(m.structural_count, 56u);
  for (auto [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{a, c}}) EXPECT_TRUE(has_spring(m, p, q, true));
  // The bending springs across them are gone: across a–b (wings c and 1), b–c (wings a and 13),
  // a–c (wings b and 11).
  EXPECT_EQ(m.springs.size() - m.structural_count, 37u);
  EXPECT_TRUE(has_spring(s, c, grid_vertex(1, 0), false));
  EXPECT_TRUE(has_spring(s, a, grid_vertex(3, 2), false));
  EXPECT_TRUE(has_spring(s, b, grid_vertex(1, 2), false));
  EXPECT_FALSE(has_spring(m, c, grid_vertex(1, 0), false));
  EXPECT_FALSE(has_spring(m, a, grid_vertex(3, 2), false));
  EXPECT_FALSE(has_spring(m, b, grid_vertex(1, 2), false));

  // Each corner loses its third of the triangle: 2e-4 − 1e-4/3 = 5e-4/3 kg.
  for (std::uint32_t v : {a, b, c}) {
    EXPECT_NEAR(m.masses[v], 5 * kTriangleMass / 3, 1e-16) << v;
    EXPECT_EQ(m.inverse_masses[v], 1 / m.masses[v]);
  }
  for (std::uint32_t v = 0; v < 25; ++v)
    if (v != a && v != b && v != c) {
      EXPECT_EQ(m.masses[v], s.masses[v]) << v;
    }
  EXPECT_NEAR(m.total_mass(), 31 * kTriangleMass, 1e-15);
  EXPECT_NEAR(s.total_mass() - m.total_mass(), kTriangleMass, 1e-16);
  EXPECT_EQ(m.mean_rest_area, s.mean_rest_area);
}

// Around vertex 12 = (2, 2) the six triangles, in turn: 10, 13, 20, 21, 18, 11. Removing 13 and
// 21 leaves the fans {20} and {18, 11, 10}, which touch only at vertex 12.
TEST(CutTopology, BowTieVertexIsSplitByFans) {
  const MassSpringSettings s = grid_settings();
  const std::uint32_t v = grid_vertex(2, 2);
  const std::uint32_t t13 = grid_triangle(2, 1, 1), t21 = grid_triangle(2, 2, 1), t20 = grid_triangle(2, 2, 0);
  ASSERT_EQ(t13, 13u);
  ASSERT_EQ(t21, 21u);
  // Without the split the surface would have a bow-tie there.
  TriMesh naive = grid_mesh();
  naive.triangles.erase(naive.triangles.begin() + t21);
  naive.triangles.erase(naive.triangles.begin() + t13);
  ASSERT_EQ(MeshTopology(naive).nonmanifold_vertices().size(), 1u);

  const CutTopology r = cut(s, {t21, t13});
  const MassSpringSettings& m = r.settings;
  ASSERT_EQ(m.vertex_count(), 26u);
  EXPECT_EQ(r.vertex_origin[25], v);  // the copy comes after all kept vertices
  for (std::uint32_t i = 0; i < 25; ++i) EXPECT_EQ(r.vertex_origin[i], i);
  EXPECT_EQ(m.rest_positions[25], s.rest_positions[v]);
  // Triangle 20 = (12, 13, 18), now the 19th, uses the copy; the fan of triangle 10 keeps 12.
  EXPECT_EQ(r.triangle_origin[19], t20);
  EXPECT_EQ(m.triangles[19], (Triangle{25, grid_vertex(3, 2), grid_vertex(3, 3)}));
  EXPECT_EQ(m.triangles[10], s.triangles[10]);
  // Masses: 12 keeps three triangles' thirds, the copy one; together 2e-4 − 2 × 1e-4/3.
  EXPECT_NEAR(m.masses[v], 3 * kTriangleMass / 3, 1e-16);
  EXPECT_NEAR(m.masses[25], kTriangleMass / 3, 1e-16);
  EXPECT_NEAR(m.masses[v] + m.masses[25], s.masses[v] - 2 * kTriangleMass / 3, 1e-16);
  EXPECT_NEAR(m.total_mass(), 30 * kTriangleMass, 1e-15);

  const MeshTopology topology(mesh_of(m));
  EXPECT_TRUE(topology.nonmanifold_vertices().empty());
  EXPECT_TRUE(topology.nonmanifold_edges().empty());
  EXPECT_EQ(topology.used_vertex_count(), 26u);
  EXPECT_EQ(m.structural_count, topology.edge_count());
  // The copy's edges carry the old edges' springs: (12, 13) became (13, 25), (12, 18) (18, 25).
  EXPECT_TRUE(has_spring(m, 25, grid_vertex(3, 2), true));
  EXPECT_TRUE(has_spring(m, 25, grid_vertex(3, 3), true));
  EXPECT_FALSE(has_spring(m, v, grid_vertex(3, 2), true));
  EXPECT_FALSE(has_spring(m, v, grid_vertex(3, 3), true));
  for (std::size_t k = 0; k < m.springs.size(); ++k)
    EXPECT_NEAR(m.springs[k].rest_length, (m.rest_positions[m.springs[k].i] - m.rest_positions[m.springs[k].j]).norm(), 1e-17)
        << k;
}

void expect_pieces_unconnected(const MassSpringSettings& m, std::size_t pieces) {
  const MeshTopology topology(mesh_of(m));
  ASSERT_EQ(topology.component_count(), pieces);
  std::vector<std::uint32_t> piece(m.vertex_count(), MeshTopology::kNone);
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (std::uint32_t v : m.triangles[t]) piece[v] = topology.triangle_component(t);
  for (const Spring& p : m.springs) EXPECT_EQ(piece[p.i], piece[p.j]) << p.i << " " << p.j;
  EXPECT_TRUE(topology.nonmanifold_vertices().empty());
}

// Column i = 2 removed: the pieces i ≤ 1 (vertices x ≤ 2) and i = 3 (x ≥ 3) share no vertex.
TEST(CutTopology, ColumnStripCutsTheSheetInTwo) {
  const MassSpringSettings s = grid_settings();
  std::vector<std::uint32_t> strip;
  for (std::uint32_t j = 0; j < 4; ++j) strip.insert(strip.end(), {grid_triangle(2, j, 0), grid_triangle(2, j, 1)});
  const MeshTopology before(grid_mesh());
  ASSERT_EQ(before.component_count(), 1u);
  const CutTopology r = cut(s, strip);
  EXPECT_EQ(r.settings.triangles.size(), 24u);
  EXPECT_EQ(r.settings.vertex_count(), 25u);
  expect_pieces_unconnected(r.settings, 2);
  EXPECT_NEAR(r.settings.total_mass(), 24 * kTriangleMass, 1e-15);
}

// The diagonal cells (k, k) removed: the pieces above and below the diagonal touch at (1, 1),
// (2, 2), (3, 3), which are split; the corners (0, 0) and (4, 4) lose all their triangles.
TEST(CutTopology, DiagonalStripSplitsAndDrops) {
  const MassSpringSettings s = grid_settings();
  std::vector<std::uint32_t> strip;
  for (std::uint32_t k = 0; k < 4; ++k) strip.insert(strip.end(), {grid_triangle(k, k, 1), grid_triangle(k, k, 0)});
  const CutTopology r = cut(s, strip);
  const MassSpringSettings& m = r.settings;
  EXPECT_EQ(m.triangles.size(), 24u);
  ASSERT_EQ(m.vertex_count(), 25u - 2u + 3u);
  // Kept vertices in order without 0 and 24, then the copies of 6, 12, 18.
  std::vector<std::uint32_t> want;
  for (std::uint32_t v = 1; v < 24; ++v) want.push_back(v);
  want.insert(want.end(), {6, 12, 18});
  EXPECT_EQ(r.vertex_origin, want);
  expect_pieces_unconnected(m, 2);
  // Each split vertex kept one triangle in each piece: 1e-4/3 kg per copy.
  for (std::uint32_t k = 1; k <= 3; ++k) {
    const std::uint32_t old = grid_vertex(k, k);
    const std::uint32_t kept_place = old - 1, copy = 22 + k;
    EXPECT_NEAR(m.masses[kept_place], kTriangleMass / 3, 1e-17) << k;
    EXPECT_NEAR(m.masses[copy], kTriangleMass / 3, 1e-17) << k;
    // The fan of the lower triangle, cell (k, k−1) below the diagonal, keeps the place.
    const std::uint32_t below = grid_triangle(k, k - 1, 1), above = grid_triangle(k - 1, k, 0);
    ASSERT_LT(below, above);
    const auto new_index = [&](std::uint32_t t) {
      return static_cast<std::size_t>(std::find(r.triangle_origin.begin(), r.triangle_origin.end(), t) - r.triangle_origin.begin());
    };
    const Triangle& tb = m.triangles[new_index(below)];
    const Triangle& ta = m.triangles[new_index(above)];
    EXPECT_NE(std::find(tb.begin(), tb.end(), kept_place), tb.end()) << k;
    EXPECT_NE(std::find(ta.begin(), ta.end(), copy), ta.end()) << k;
  }
  EXPECT_NEAR(m.total_mass(), 24 * kTriangleMass, 1e-15);
}

TEST(CutTopology, ClosedSphereOpensWithThreeBoundaryEdges) {
  MassSpringMaterial mat = sheet_material();
  mat.k_volume = 1000;
  const MassSpringSettings s = MassSpringSettings::build(make_icosphere(0.05, 2), mat);
  ASSERT_TRUE(s.closed);
  ASSERT_EQ(MeshTopology(mesh_of(s)).boundary_edges().size(), 0u);
  const CutTopology r = cut(s, {0});
  EXPECT_FALSE(r.settings.closed);
  EXPECT_EQ(r.settings.rest_volume, s.rest_volume);
  EXPECT_EQ(r.settings.k_volume, 1000);
  EXPECT_EQ(r.settings.triangles.size(), 319u);
  const MeshTopology topology(mesh_of(r.settings));
  EXPECT_EQ(topology.boundary_edges().size(), 3u);
  EXPECT_EQ(topology.euler_characteristic(), 1);  // a disc
  EXPECT_EQ(r.settings.springs.size() - r.settings.structural_count, 480u - 3u);
}

TEST(CutTopology, EverythingRemovedIsEmpty) {
  const MassSpringSettings s = grid_settings();
  const CutTopology r = cut(s, iota_vector(32));
  EXPECT_TRUE(r.settings.triangles.empty());
  EXPECT_EQ(r.settings.vertex_count(), 0u);
  EXPECT_TRUE(r.settings.rest_positions.empty());
  EXPECT_TRUE(r.settings.springs.empty());
  EXPECT_EQ(r.settings.structural_count, 0u);
  EXPECT_TRUE(r.vertex_origin.empty());
  EXPECT_TRUE(r.triangle_origin.empty());
  EXPECT_EQ(r.settings.mean_rest_area, s.mean_rest_area);
  const CutTopology again = cut(r.settings, {0, 1});
  EXPECT_TRUE(again.settings.triangles.empty());
  EXPECT_EQ(again.settings.vertex_count(), 0u);
}

// Each corner's lumped third of the triangles, as rule 4 defines the share that leaves.
Real removed_share(const MassSpringSettings& s, const std::set<std::uint32_t>& removed) {
  std::vector<Real> all(s.vertex_count(), 0.0);
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    for (std::uint32_t v : s.triangles[t]) all[v] += s.rest_areas[t] / 3;
  Real gone = 0;
  for (std::uint32_t t : removed)
    for (std::uint32_t v : s.triangles[t]) gone += s.masses[v] * (s.rest_areas[t] / 3) / all[v];
  return gone;
}

TEST(CutTopology, SeededSoakKeepsTheModelConsistent) {
  MassSpringMaterial mat = sheet_material();
  const TriMesh capsule = make_capsule(0.02, 0.05, 16, 10);  // 640 triangles, closed
  MassSpringSettings s = MassSpringSettings::build(capsule, mat);
  ASSERT_TRUE(s.closed);
  ASSERT_EQ(s.triangles.size(), 640u);
  const Real mass_per_area = s.total_mass() / (s.mean_rest_area * 640);
  std::mt19937 rng(20240611u);
  std::size_t splits = 0, drops = 0;
  for (int call = 0; call < 200; ++call) {
    const std::size_t n_tris = s.triangles.size();
    ASSERT_GT(n_tris, 0u);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(n_tris - 1));
    std::vector<std::uint32_t> removed(std::uniform_int_distribution<int>(1, 3)(rng));
    for (std::uint32_t& t : removed) t = pick(rng);
    if (call % 17 == 0) removed.push_back(static_cast<std::uint32_t>(n_tris + 3));  // ignored
    const std::set<std::uint32_t> unique(removed.begin(), removed.end());
    std::set<std::uint32_t> valid;
    Real removed_area = 0;
    for (std::uint32_t t : unique)
      if (t < n_tris) {
        valid.insert(t);
        removed_area += s.rest_areas[t];
      }

    const CutTopology r = remove_triangles(s, removed);
    const MassSpringSettings& m = r.settings;
    SCOPED_TRACE(call);
    const std::size_t n_verts = m.vertex_count();
    ASSERT_EQ(m.triangles.size(), n_tris - valid.size());
    ASSERT_EQ(m.rest_positions.size(), n_verts);
    ASSERT_EQ(m.home_positions.size(), n_verts);
    ASSERT_EQ(m.inverse_masses.size(), n_verts);
    ASSERT_EQ(m.fixed.size(), n_verts);
    ASSERT_EQ(r.vertex_origin.size(), n_verts);
    ASSERT_EQ(r.triangle_origin.size(), m.triangles.size());
    for (const Triangle& tri : m.triangles)
      for (std::uint32_t v : tri) ASSERT_LT(v, n_verts);

    const MeshTopology topology(mesh_of(m));
    EXPECT_EQ(topology.used_vertex_count(), n_verts);
    EXPECT_TRUE(topology.nonmanifold_vertices().empty());
    EXPECT_TRUE(topology.nonmanifold_edges().empty());
    EXPECT_FALSE(m.closed);
    EXPECT_EQ(m.mean_rest_area, s.mean_rest_area);
    std::size_t interior = 0;
    for (std::size_t e = 0; e < topology.edge_count(); ++e) interior += topology.edge_valence(e) == 2;
    EXPECT_EQ(m.structural_count, topology.edge_count());
    EXPECT_EQ(m.springs.size() - m.structural_count, interior);
    // Each spring copies the old one between the same (original) vertices, of the same kind.
    ASSERT_EQ(r.spring_origin.size(), m.springs.size());
    for (std::size_t k = 0; k < m.springs.size(); ++k) {
      const Spring& p = m.springs[k];
      const Spring& was = s.springs[r.spring_origin[k]];
      EXPECT_EQ(std::minmax(r.vertex_origin[p.i], r.vertex_origin[p.j]), std::minmax(was.i, was.j)) << k;
      EXPECT_EQ(k < m.structural_count, r.spring_origin[k] < s.structural_count) << k;
      EXPECT_EQ(p.stiffness, was.stiffness) << k;
      EXPECT_EQ(p.rest_length, was.rest_length) << k;
    }
    for (std::size_t k = 0; k < m.springs.size(); ++k) {
      const Spring& p = m.springs[k];
      ASSERT_LT(p.i, p.j);
      ASSERT_LT(p.j, n_verts);
      EXPECT_NEAR(p.rest_length, (m.rest_positions[p.j] - m.rest_positions[p.i]).norm(), 1e-16) << k;
      EXPECT_EQ(p.stiffness, k < m.structural_count ? mat.k_structural : mat.k_bending) << k;
    }
    // build()'s order: structural springs along the sorted edges, then bending springs across
    // the interior edges in the same order, between their wing vertices.
    for (std::size_t e = 0; e < topology.edge_count() && e < m.structural_count; ++e) {
      EXPECT_EQ(m.springs[e].i, topology.edge(e).v0) << e;
      EXPECT_EQ(m.springs[e].j, topology.edge(e).v1) << e;
    }
    std::size_t bend = m.structural_count;
    for (std::size_t e = 0; e < topology.edge_count() && bend < m.springs.size(); ++e) {
      if (topology.edge_valence(e) != 2) continue;
      const auto [a, b] = topology.opposite_vertices(e);
      EXPECT_EQ(m.springs[bend].i, std::min(a, b)) << e;
      EXPECT_EQ(m.springs[bend].j, std::max(a, b)) << e;
      ++bend;
    }

    // Origins: strictly increasing triangles with the same corners, positions through the map.
    std::vector<std::uint8_t> seen(s.vertex_count(), 0);
    std::size_t distinct = 0;
    for (std::size_t i = 0; i < n_verts; ++i) {
      const std::uint32_t o = r.vertex_origin[i];
      ASSERT_LT(o, s.vertex_count());
      EXPECT_EQ(m.rest_positions[i], s.rest_positions[o]);
      EXPECT_EQ(m.home_positions[i], s.home_positions[o]);
      EXPECT_EQ(m.fixed[i], s.fixed[o]);
      distinct += seen[o] == 0;
      seen[o] = 1;
      EXPECT_TRUE(m.masses[i] > 0 && std::isfinite(m.masses[i])) << i;
      EXPECT_EQ(m.inverse_masses[i], 1 / m.masses[i]);
    }
    splits += n_verts - distinct;
    drops += s.vertex_count() - distinct;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const std::uint32_t o = r.triangle_origin[t];
      ASSERT_LT(o, n_tris);
      EXPECT_EQ(valid.count(o), 0u);
      if (t > 0) {
        EXPECT_GT(o, r.triangle_origin[t - 1]);
      }
      for (int k = 0; k < 3; ++k) EXPECT_EQ(r.vertex_origin[m.triangles[t][k]], s.triangles[o][k]);
      EXPECT_EQ(m.rest_areas[t], s.rest_areas[o]);
    }

    // Mass: exactly the removed thirds left, which is the removed area × the model's mass per area
    // (build() lumped M·share/A, and every cut keeps m = (M/A)·share).
    const Real before = s.total_mass(), after = m.total_mass();
    EXPECT_NEAR(after, before - removed_share(s, valid), 1e-12 * before);
    EXPECT_NEAR(after, before - mass_per_area * removed_area, 1e-12 * before);

    s = m;
  }
  // The soak did exercise splits and drops (the test would be weak otherwise).
  EXPECT_GT(splits, 0u);
  EXPECT_GT(drops, 0u);
}

}  // namespace
}  // namespace trocar
