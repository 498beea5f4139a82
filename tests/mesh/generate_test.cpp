#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/topology.h"
#include "trocar/mesh/validate.h"
#include "mesh_test_util.h"

namespace trocar {
namespace {

using test::min_plane_distance;

constexpr Real kPi = std::numbers::pi_v<Real>;


TEST(Generate, IcosphereCountsAndClean) {
  for (int n = 0; n <= 4; ++n) {
    const TriMesh m = make_icosphere(0.02, n);
    const std::size_t p = std::size_t{1} << (2 * n);  // 4ⁿ
    EXPECT_EQ(m.positions.size(), 10 * p + 2) << n;
    EXPECT_EQ(m.triangles.size(), 20 * p) << n;
    EXPECT_EQ(m.normals.size(), m.positions.size());
    const MeshReport r = validate(m);
    EXPECT_EQ(r.edges, 30 * p);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_TRUE(r.is_clean()) << n << ::testing::PrintToString(r.defects());
    for (const Vec3& v : m.positions) EXPECT_NEAR(v.norm(), 0.02, 1e-15);
  }
}

TEST(Generate, IcosphereVolumeAndAreaConverge) {
  const Real r = 0.05;
  const Real sphere_volume = 4.0 / 3.0 * kPi * r * r * r;
  const Real sphere_area = 4 * kPi * r * r;
  Real previous_error = std::numeric_limits<Real>::infinity();
  for (int n = 0; n <= 5; ++n) {
    const TriMesh m = make_icosphere(r, n);
    const MeshReport rep = validate(m);
    const Real d = min_plane_distance(m);
    // Inscribed polyhedron: between the inscribed ball (radius d) and the sphere.
    EXPECT_LT(rep.signed_volume, sphere_volume);
    EXPECT_GE(rep.signed_volume, 4.0 / 3.0 * kPi * d * d * d);
    EXPECT_LT(rep.area, sphere_area);
    EXPECT_GE(rep.area, 4 * kPi * d * d);
    const Real error = (sphere_volume - rep.signed_volume) / sphere_volume;
    EXPECT_LT(error, previous_error / 3) << n;  // O(h²): ≈ ×4 per level
    previous_error = error;
  }
  EXPECT_LT(previous_error, 2e-3);  // level 5 (20480 T)
  const TriMesh ico = make_icosphere(1.0, 0);
  // Level 0 is the regular icosahedron: V = (5/12)(3+√5)a³, a = 4/√(10+2√5) for r = 1.
  const Real a = 4 / std::sqrt(10 + 2 * std::sqrt(5.0));
  EXPECT_NEAR(validate(ico).signed_volume, 5.0 / 12.0 * (3 + std::sqrt(5.0)) * a * a * a, 1e-14);
}

TEST(Generate, SheetFlatAndBulged) {
  const TriMesh flat = make_sheet(0.3, 0.2, 6, 4);
  EXPECT_EQ(flat.positions.size(), 35u);
  EXPECT_EQ(flat.triangles.size(), 48u);
  const MeshReport r = validate(flat);
  EXPECT_EQ(r.boundary_edges, 20u);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(r.is_clean_open()) << ::testing::PrintToString(r.defects());
  EXPECT_FALSE(r.is_clean());
  EXPECT_NEAR(r.area, 0.06, 1e-16);
  EXPECT_NEAR(r.bounds.min.x(), -0.15, 1e-16);
  EXPECT_NEAR(r.bounds.max.y(), 0.1, 1e-16);
  for (std::size_t t = 0; t < flat.triangles.size(); ++t) EXPECT_GT(flat.triangle_normal_area2(t).z(), 0);

  const TriMesh bulged = make_sheet(0.3, 0.2, 30, 20, 0.05);
  const MeshReport b = validate(bulged);
  EXPECT_TRUE(b.is_clean_open());
  EXPECT_EQ(b.boundary_edges, 100u);
  EXPECT_GT(b.area, 0.06);
  EXPECT_NEAR(b.bounds.max.z(), 0.05, 1e-15);  // centre vertex (15, 10) is on the peak
  EXPECT_EQ(b.bounds.min.z(), 0.0);
  for (std::size_t t = 0; t < bulged.triangles.size(); ++t) EXPECT_GT(bulged.triangle_normal_area2(t).z(), 0);
  EXPECT_THROW(make_sheet(0.3, 0.2, 0, 4), Error);
}

TEST(Generate, CylinderCappedIsExact) {
  const Real r = 0.0025, length = 0.35;
  for (std::size_t s : {3u, 8u, 32u}) {
    const TriMesh m = make_cylinder(r, length, s);
    EXPECT_EQ(m.positions.size(), 2 * s + 2);
    EXPECT_EQ(m.triangles.size(), 4 * s);
    const MeshReport rep = validate(m);
    EXPECT_TRUE(rep.is_clean()) << s << ::testing::PrintToString(rep.defects());
    const Real sn = static_cast<Real>(s);
    const Real polygon = 0.5 * sn * r * r * std::sin(2 * kPi / sn);
    EXPECT_NEAR(rep.signed_volume, polygon * length, 1e-14 * polygon * length);
    const Real side = sn * 2 * r * std::sin(kPi / sn) * length;
    EXPECT_NEAR(rep.area, side + 2 * polygon, 1e-13 * (side + 2 * polygon));
    EXPECT_NEAR(rep.bounds.min.z(), 0.0, 0);
    EXPECT_NEAR(rep.bounds.max.z(), length, 0);
  }
}

TEST(Generate, CylinderUncappedIsAnOpenTube) {
  const TriMesh m = make_cylinder(0.01, 0.1, 12, false);
  EXPECT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(m.triangles.size(), 24u);
  const MeshReport r = validate(m);
  EXPECT_EQ(r.boundary_edges, 24u);
  EXPECT_EQ(r.euler_characteristic, 0);  // an annulus
  EXPECT_TRUE(r.is_clean_open());
  // Outward: every side normal points away from the axis.
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto c = m.corners(t);
    const Vec3 mid = (c[0] + c[1] + c[2]) / 3;
    EXPECT_GT(m.triangle_normal_area2(t).dot(Vec3(mid.x(), mid.y(), 0)), 0);
  }
}

TEST(Generate, CapsuleCountsAndVolumeBounds) {
  const Real r = 0.005, length = 0.03;
  const Real capsule = kPi * r * r * length + 4.0 / 3.0 * kPi * r * r * r;
  for (auto [s, rings] : {std::pair<std::size_t, std::size_t>{3, 1}, {8, 2}, {16, 4}, {64, 16}}) {
    const TriMesh m = make_capsule(r, length, s, rings);
    EXPECT_EQ(m.positions.size(), 2 * rings * s + 2);
    EXPECT_EQ(m.triangles.size(), 4 * rings * s);
    const MeshReport rep = validate(m);
    EXPECT_TRUE(rep.is_clean()) << s << "x" << rings << ::testing::PrintToString(rep.defects());
    EXPECT_EQ(rep.euler_characteristic, 2);
    EXPECT_NEAR(rep.bounds.min.z(), -r, 1e-18);
    EXPECT_NEAR(rep.bounds.max.z(), length + r, 1e-17);
    // Inscribed in the capsule, and containing the capsule of radius d, where d is the least
    // distance from the axis segment's end points to a face plane.
    Real d = std::numeric_limits<Real>::infinity();
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const Vec3 n = m.triangle_normal_area2(t).normalized();
      const Vec3& a = m.positions[m.triangles[t][0]];
      d = std::min({d, n.dot(a), n.dot(a - Vec3(0, 0, length))});
    }
    EXPECT_LT(rep.signed_volume, capsule);
    EXPECT_GE(rep.signed_volume, kPi * d * d * length + 4.0 / 3.0 * kPi * d * d * d);
  }
  const MeshReport fine = validate(make_capsule(r, length, 128, 32));
  EXPECT_NEAR(fine.signed_volume, capsule, 2e-3 * capsule);
  EXPECT_THROW(make_capsule(r, 0, 8, 2), Error);
}

TEST(Generate, BoxIsExact) {
  const TriMesh m = make_box(0.1, 0.2, 0.4);
  EXPECT_EQ(m.positions.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  const MeshReport r = validate(m);
  EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  EXPECT_NEAR(r.signed_volume, 0.008, 1e-17);
  EXPECT_NEAR(r.area, 2 * (0.02 + 0.04 + 0.08), 1e-16);
  EXPECT_EQ(r.bounds.min, Vec3(-0.05, -0.1, -0.2));
  // Every face's normal is axis-aligned and outward.
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Vec3 n = m.triangle_normal_area2(t).normalized();
    const auto c = m.corners(t);
    EXPECT_GT(n.dot(c[0] + c[1] + c[2]), 0);
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-15);
  }
  EXPECT_THROW(make_box(0, 1, 1), Error);
}

TEST(Generate, IcosphereBendingWings) {
  // Every edge of a closed mesh has two wing vertices, neither on the edge.
  const TriMesh m = make_icosphere(1.0, 2);
  const MeshTopology topo(m);
  for (std::size_t e = 0; e < topo.edge_count(); ++e) {
    const auto w = topo.opposite_vertices(e);
    ASSERT_NE(w[0], MeshTopology::kNone);
    ASSERT_NE(w[1], MeshTopology::kNone);
    EXPECT_NE(w[0], w[1]);
    EXPECT_NE(w[0], topo.edge(e).v0);
    EXPECT_NE(w[1], topo.edge(e).v1);
  }
}

}  // namespace
}  // namespace trocar
