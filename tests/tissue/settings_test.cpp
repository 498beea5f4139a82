// MassSpringSettings::build: spring counts, rest state, mass lumping, fixed selections, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <utility>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/topology.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {
namespace {

MassSpringMaterial material_with_mass(Real mass) {
  MassSpringMaterial m;
  m.mass = mass;
  return m;
}

TEST(TissueSettings, IcosphereSpringCounts) {
  for (int n = 0; n <= 3; ++n) {
    const TriMesh mesh = make_icosphere(0.05, n);
    const MassSpringSettings s = MassSpringSettings::build(mesh, material_with_mass(0.1));
    const std::size_t e = 30 * (std::size_t{1} << (2 * n));  // E = 30·4ⁿ
    EXPECT_EQ(s.structural_count, e) << n;
    EXPECT_EQ(s.springs.size(), 2 * e) << n;  // every edge is interior: one bending spring each
    EXPECT_EQ(s.vertex_count(), mesh.positions.size());
    EXPECT_EQ(s.triangles.size(), mesh.triangles.size());
    EXPECT_TRUE(s.closed);
    EXPECT_NEAR(s.rest_volume, mesh.signed_volume(), 1e-18);
    EXPECT_GT(s.rest_volume, 0);
  }
}

TEST(TissueSettings, SpringsMatchTheMesh) {
  const TriMesh mesh = make_icosphere(0.05, 2);
  MassSpringMaterial mat = material_with_mass(0.1);
  mat.k_structural = 123;
  mat.k_bending = 7;
  mat.spring_damping = 0.25;
  const MassSpringSettings s = MassSpringSettings::build(mesh, mat);
  const MeshTopology topology(mesh);
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const Edge& e : topology.edges()) edges.insert({std::min(e.v0, e.v1), std::max(e.v0, e.v1)});
  for (std::size_t k = 0; k < s.springs.size(); ++k) {
    const Spring& p = s.springs[k];
    const bool structural = k < s.structural_count;
    EXPECT_NEAR(p.rest_length, (mesh.positions[p.j] - mesh.positions[p.i]).norm(), 1e-15);
    EXPECT_GT(p.rest_length, 0);
    EXPECT_EQ(p.stiffness, structural ? 123 : 7);
    EXPECT_EQ(p.damping, 0.25);
    // Structural springs are mesh edges; bending springs join two vertices that share no edge
    // on an icosphere (they are opposite across an edge).
    EXPECT_EQ(edges.count({std::min(p.i, p.j), std::max(p.i, p.j)}), structural ? 1u : 0u) << k;
  }
}

TEST(TissueSettings, SheetBendingSpringsOnInteriorEdgesOnly) {
  const std::size_t nx = 5, ny = 3;
  const MassSpringSettings s = MassSpringSettings::build(make_sheet(0.2, 0.1, nx, ny), material_with_mass(0.05));
  const std::size_t e = nx * (ny + 1) + ny * (nx + 1) + nx * ny;  // rows, columns, diagonals
  const std::size_t boundary = 2 * (nx + ny);
  EXPECT_EQ(s.structural_count, e);
  EXPECT_EQ(s.springs.size() - s.structural_count, e - boundary);
  EXPECT_FALSE(s.closed);
  EXPECT_EQ(s.rest_volume, 0);
  EXPECT_NEAR(s.mean_rest_area, 0.2 * 0.1 / static_cast<Real>(2 * nx * ny), 1e-15);
}

TEST(TissueSettings, NoBendingSpringsWhenKBendingIsZero) {
  MassSpringMaterial mat = material_with_mass(0.1);
  mat.k_bending = 0;
  const MassSpringSettings s = MassSpringSettings::build(make_icosphere(0.05, 1), mat);
  EXPECT_EQ(s.springs.size(), s.structural_count);
  EXPECT_EQ(s.structural_count, 120u);
}

TEST(TissueSettings, RestAreasAndCoefficients) {
  const TriMesh mesh = make_icosphere(0.05, 2);
  MassSpringMaterial mat = material_with_mass(0.1);
  mat.k_area = 11;
  mat.k_volume = 22;
  mat.k_home = 33;
  mat.damping = 0.7;
  const Vec3 g(0, -9.81, 0);
  const MassSpringSettings s = MassSpringSettings::build(mesh, mat, {}, g);
  Real sum = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    EXPECT_NEAR(s.rest_areas[t], 0.5 * mesh.triangle_normal_area2(t).norm(), 1e-18);
    sum += s.rest_areas[t];
  }
  EXPECT_NEAR(s.mean_rest_area, sum / static_cast<Real>(mesh.triangles.size()), 1e-18);
  EXPECT_EQ(s.k_area, 11);
  EXPECT_EQ(s.k_volume, 22);
  EXPECT_EQ(s.k_home, 33);
  EXPECT_EQ(s.damping, 0.7);
  EXPECT_EQ(s.gravity, g);
  EXPECT_EQ(s.rest_positions, mesh.positions);
  const MassSpringState state = MassSpringState::at_rest(s);
  EXPECT_EQ(state.positions, mesh.positions);
  for (const Vec3& v : state.velocities) EXPECT_EQ(v, Vec3::Zero());
}

TEST(TissueSettings, TotalMassGivenOrFromDensity) {
  const TriMesh sphere = make_icosphere(0.05, 2);
  EXPECT_NEAR(MassSpringSettings::build(sphere, material_with_mass(0.3)).total_mass(), 0.3, 1e-14);

  MassSpringMaterial by_density;
  by_density.mass = 0;
  by_density.density = 1000;
  const MassSpringSettings closed = MassSpringSettings::build(sphere, by_density);
  EXPECT_NEAR(closed.total_mass(), 1000 * sphere.signed_volume(), 1e-12);
  EXPECT_NEAR(closed.total_mass(), 1000 * 4.0 / 3.0 * std::numbers::pi * 0.05 * 0.05 * 0.05, 0.05);

  by_density.sheet_thickness = 0.003;
  const MassSpringSettings sheet = MassSpringSettings::build(make_sheet(0.2, 0.1, 4, 4), by_density);
  EXPECT_NEAR(sheet.total_mass(), 1000 * 0.2 * 0.1 * 0.003, 1e-14);
}

TEST(TissueSettings, MassIsLumpedByAdjacentArea) {
  // Icosahedron: all 12 vertices alike, so each gets M/12.
  const MassSpringSettings ico = MassSpringSettings::build(make_icosphere(0.05, 0), material_with_mass(1.2));
  for (Real m : ico.masses) EXPECT_NEAR(m, 0.1, 1e-15);

  // A flat sheet: m_i = M · (Σ adjacent triangle areas / 3) / total area.
  const TriMesh sheet = make_sheet(0.3, 0.2, 3, 2);
  const MassSpringSettings s = MassSpringSettings::build(sheet, material_with_mass(0.6));
  std::vector<Real> share(sheet.positions.size(), 0.0);
  Real total_area = 0;
  for (std::size_t t = 0; t < sheet.triangles.size(); ++t) {
    const Real a = 0.5 * sheet.triangle_normal_area2(t).norm();
    total_area += a;
    for (std::uint32_t v : sheet.triangles[t]) share[v] += a / 3;
  }
  Real sum = 0;
  for (std::size_t i = 0; i < share.size(); ++i) {
    EXPECT_NEAR(s.masses[i], 0.6 * share[i] / total_area, 1e-15) << i;
    EXPECT_NEAR(s.inverse_masses[i], 1 / s.masses[i], 1e-9);
    sum += s.masses[i];
  }
  EXPECT_NEAR(sum, 0.6, 1e-14);
  EXPECT_NEAR(s.total_mass(), 0.6, 1e-14);
}

std::size_t count_fixed(const MassSpringSettings& s) {
  std::size_t c = 0;
  for (std::size_t i = 0; i < s.vertex_count(); ++i) {
    EXPECT_EQ(s.inverse_masses[i] == 0, s.fixed[i] == 1) << i;
    EXPECT_GT(s.masses[i], 0);
    c += s.fixed[i];
  }
  return c;
}

TEST(TissueSettings, FixedByIndexPlaneAndBox) {
  const TriMesh mesh = make_icosphere(0.05, 2);
  const MassSpringMaterial mat = material_with_mass(0.1);
  EXPECT_EQ(count_fixed(MassSpringSettings::build(mesh, mat)), 0u);

  FixedSelection by_index;
  by_index.indices = {0, 5, 17, 5};
  const MassSpringSettings a = MassSpringSettings::build(mesh, mat, by_index);
  EXPECT_EQ(count_fixed(a), 3u);
  EXPECT_TRUE(a.fixed[0] && a.fixed[5] && a.fixed[17]);

  FixedSelection below;
  below.below_plane = Plane{Vec3(0, 0, 0.01), Vec3(0, 0, 2)};  // z < 0.01; normal need not be unit
  const MassSpringSettings b = MassSpringSettings::build(mesh, mat, below);
  std::size_t expected = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const bool want = mesh.positions[i].z() < 0.01;
    EXPECT_EQ(b.fixed[i] == 1, want) << i;
    expected += want;
  }
  EXPECT_EQ(count_fixed(b), expected);
  EXPECT_GT(expected, 0u);

  FixedSelection in_box;
  in_box.inside_box = Aabb{Vec3(0.02, -1, -1), Vec3(1, 1, 1)};  // x ≥ 0.02
  const MassSpringSettings c = MassSpringSettings::build(mesh, mat, in_box);
  expected = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const bool want = mesh.positions[i].x() >= 0.02;
    EXPECT_EQ(c.fixed[i] == 1, want) << i;
    expected += want;
  }
  EXPECT_EQ(count_fixed(c), expected);

  // The union of all three.
  FixedSelection all = in_box;
  all.indices = by_index.indices;
  all.below_plane = below.below_plane;
  const MassSpringSettings u = MassSpringSettings::build(mesh, mat, all);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    EXPECT_EQ(u.fixed[i], a.fixed[i] | b.fixed[i] | c.fixed[i]) << i;
}

TEST(TissueSettings, RejectsBadInput) {
  const TriMesh mesh = make_icosphere(0.05, 1);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  const auto expect_error = [&](MassSpringMaterial m, const char* field) {
    EXPECT_THROW(MassSpringSettings::build(mesh, m), Error) << field;
  };
  for (Real bad : {-1.0, nan, inf}) {
    MassSpringMaterial m;
    m.mass = bad; expect_error(m, "mass");
    m = {}; m.density = bad; expect_error(m, "density");
    m = {}; m.sheet_thickness = bad; expect_error(m, "sheet_thickness");
    m = {}; m.k_structural = bad; expect_error(m, "k_structural");
    m = {}; m.k_bending = bad; expect_error(m, "k_bending");
    m = {}; m.damping = bad; expect_error(m, "damping");
    m = {}; m.spring_damping = bad; expect_error(m, "spring_damping");
    m = {}; m.k_area = bad; expect_error(m, "k_area");
    m = {}; m.k_volume = bad; expect_error(m, "k_volume");
    m = {}; m.k_home = bad; expect_error(m, "k_home");
  }
  MassSpringMaterial no_mass;
  no_mass.mass = 0;
  no_mass.density = 0;
  EXPECT_THROW(MassSpringSettings::build(mesh, no_mass), Error);

  // The error names the field.
  try {
    MassSpringMaterial m;
    m.k_area = -2;
    MassSpringSettings::build(mesh, m);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("k_area"), std::string::npos) << e.what();
  }

  FixedSelection out_of_range;
  out_of_range.indices = {static_cast<std::uint32_t>(mesh.positions.size())};
  EXPECT_THROW(MassSpringSettings::build(mesh, {}, out_of_range), Error);

  EXPECT_THROW(MassSpringSettings::build(TriMesh{}, {}), Error);
  TriMesh bad_index = mesh;
  bad_index.triangles[3][1] = 999;
  EXPECT_THROW(MassSpringSettings::build(bad_index, {}), Error);
  TriMesh bad_position = mesh;
  bad_position.positions[2].y() = nan;
  EXPECT_THROW(MassSpringSettings::build(bad_position, {}), Error);
}

}  // namespace
}  // namespace trocar
