#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "trocar/core/error.h"
#include "trocar/mesh/anatomy.h"
#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

/// Σ of the triangles' area vectors (m²): for an open surface, the area it projects onto each
/// coordinate plane (boundary-dependent only); +z for a sheet wound counter-clockwise from +z.
Vec3 area_vector(const TriMesh& m) {
  Vec3 s = Vec3::Zero();
  for (std::size_t t = 0; t < m.triangles.size(); ++t) s += 0.5 * m.triangle_normal_area2(t);
  return s;
}

TEST(Anatomy, HerniaPeritoneumCountsAndClean) {
  const Real w = 0.12, h = 0.10, R = 0.015, D = 0.025;
  const std::size_t s = 32, ks = 6, ka = 8;
  const TriMesh m = make_hernia_peritoneum(w, h, R, D, s, ks, ka);
  const std::size_t K = ks + ka;
  EXPECT_EQ(m.positions.size(), 1 + s * K);
  EXPECT_EQ(m.triangles.size(), s * (2 * K - 1));
  const MeshReport r = validate(m);
  EXPECT_TRUE(r.is_clean_open()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.boundary_edges, s);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  // Bounds: the rectangle in x, y (corners are vertices), z from the sheet to the apex.
  EXPECT_NEAR(r.bounds.min.x(), -w / 2, 1e-15);
  EXPECT_NEAR(r.bounds.max.y(), h / 2, 1e-15);
  EXPECT_EQ(r.bounds.min.z(), 0.0);
  EXPECT_EQ(r.bounds.max.z(), D);
  // The area vector of an open surface depends only on its border: the rectangle, w·h along +z
  // (counter-clockwise from +z, the sac's outside facing +z).
  const Vec3 av = area_vector(m);
  EXPECT_NEAR(av.z(), w * h, 1e-12);
  EXPECT_NEAR(av.x(), 0, 1e-15);
  EXPECT_NEAR(av.y(), 0, 1e-15);
  // Neck ring (index 1 + (ks−1)·s ..) on the circle of radius R at z = 0; sac apex faces +z.
  for (std::size_t i = 0; i < s; ++i) {
    const Vec3& p = m.positions[1 + (ks - 1) * s + i];
    EXPECT_NEAR(std::hypot(p.x(), p.y()), R, 1e-15);
    EXPECT_EQ(p.z(), 0.0);
  }
  EXPECT_GT(m.triangle_normal_area2(0).z(), 0);
  // Flat part's area = w·h − neck polygon area; the sac's area exceeds its disc's.
  const Real neck_polygon_max = kPi * R * R;
  EXPECT_GT(r.area, w * h - neck_polygon_max + 0.5 * kPi * R * R);
}

TEST(Anatomy, HerniaPeritoneumRejectsBadSizes) {
  EXPECT_THROW(make_hernia_peritoneum(0.1, 0.1, 0.05, 0.02, 16, 4, 4), Error);  // R = h/2
  EXPECT_THROW(make_hernia_peritoneum(0.1, 0.1, 0.02, 0, 16, 4, 4), Error);
  EXPECT_THROW(make_hernia_peritoneum(0.1, 0.1, 0.02, 0.02, 18, 4, 4), Error);  // not 4·q
  EXPECT_THROW(make_hernia_peritoneum(0.1, 0.1, 0.02, 0.02, 16, 0, 4), Error);
}

TEST(Anatomy, AbdominalWallOpenSheet) {
  const Real w = 0.2, h = 0.16, R = 0.02;
  const std::size_t s = 24, rings = 5;
  const TriMesh m = make_abdominal_wall(w, h, 0, R, s, rings);
  EXPECT_EQ(m.positions.size(), s * (rings + 1));
  EXPECT_EQ(m.triangles.size(), 2 * s * rings);
  const MeshReport r = validate(m);
  EXPECT_TRUE(r.is_clean_open()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.boundary_edges, 2 * s);
  EXPECT_EQ(r.euler_characteristic, 0);
  // The hole is the regular-ish polygon inscribed in the circle at the border's angles: its
  // area is Σ ½R² sin(Δθ_i); the sheet's area is w·h minus that (flat, so = area vector).
  Real hole = 0;
  for (std::size_t i = 0; i < s; ++i) {
    const Vec3& a = m.positions[i];
    const Vec3& b = m.positions[(i + 1) % s];
    EXPECT_NEAR(std::hypot(a.x(), a.y()), R, 1e-15);
    hole += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  EXPECT_GT(hole, 0.9 * kPi * R * R);
  EXPECT_LT(hole, kPi * R * R);
  EXPECT_NEAR(r.area, w * h - hole, 1e-12);
  EXPECT_NEAR(area_vector(m).z(), w * h - hole, 1e-12);
}

TEST(Anatomy, AbdominalWallClosedSlab) {
  const Real w = 0.2, h = 0.16, t = 0.01, R = 0.02;
  const std::size_t s = 24, rings = 5;
  const TriMesh m = make_abdominal_wall(w, h, t, R, s, rings);
  EXPECT_EQ(m.positions.size(), 2 * s * (rings + 1));
  EXPECT_EQ(m.triangles.size(), 4 * s * (rings + 1));
  const MeshReport r = validate(m);
  EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.euler_characteristic, 0);  // a torus: one hole through it
  EXPECT_EQ(r.orientation, Orientation::kOutward);
  const TriMesh sheet = make_abdominal_wall(w, h, 0, R, s, rings);
  EXPECT_NEAR(r.signed_volume, validate(sheet).area * t, 1e-14);
  EXPECT_NEAR(r.bounds.max.z(), t / 2, 1e-16);
  EXPECT_NEAR(r.bounds.min.z(), -t / 2, 1e-16);
}

TEST(Anatomy, LiverLobeClosedAndVolume) {
  const Real L = 0.16, W = 0.10, T = 0.06;
  for (int n = 0; n <= 3; ++n) {
    const TriMesh m = make_liver_lobe(L, W, T, n);
    const std::size_t p = std::size_t{1} << (2 * n);
    EXPECT_EQ(m.positions.size(), 10 * p + 2);
    EXPECT_EQ(m.triangles.size(), 20 * p);
    const MeshReport r = validate(m);
    EXPECT_TRUE(r.is_clean()) << n << ::testing::PrintToString(r.defects());
    EXPECT_EQ(r.euler_characteristic, 2);
  }
  const TriMesh m = make_liver_lobe(L, W, T, 4, 0.5, 0.3);
  const MeshReport r = validate(m);
  // (2/3)π·a·b·c·(1 + flatten): the top half-ellipsoid plus the flattened bottom half.
  const Real expected = 2.0 / 3.0 * kPi * (L / 2) * (W / 2) * (T / 2) * 1.5;
  EXPECT_LT(r.signed_volume, expected);
  EXPECT_GT(r.signed_volume, 0.99 * expected);
  EXPECT_NEAR(r.bounds.max.x(), L / 2, 1e-15);
  EXPECT_NEAR(r.bounds.min.y(), -W / 2, 1e-15);
  // Top pole (x̂ = 0): c·1; bottom pole: −c·flatten.
  EXPECT_NEAR(r.bounds.min.z(), -T / 2 * 0.5, 0.02 * T);
  EXPECT_THROW(make_liver_lobe(L, W, T, 2, 0.0), Error);
  EXPECT_THROW(make_liver_lobe(L, W, T, 2, 0.5, 1.0), Error);
}

}  // namespace
}  // namespace trocar
