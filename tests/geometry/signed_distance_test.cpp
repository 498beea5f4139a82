#include "trocar/geometry/signed_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/core/error.h"

namespace trocar {
namespace {

// The meshes come from the mesh module's generators (tests may depend on any module).
TriMesh cube_mesh(Real h) { return make_box(2 * h, 2 * h, 2 * h); }
TriMesh sphere_mesh(int levels, Real radius) { return make_icosphere(radius, levels); }

// Exact signed distance to the box [−h, h]³: outside, the length of the excess over the box;
// inside, minus the distance to the nearest face.
Real box_sdf(const Vec3& p, Real h) {
  const Vec3 q = p.cwiseAbs() - Vec3::Constant(h);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), Real{0});
}

TEST(MeshDistance, CubeIsExactInsideAndOutside) {
  const auto cube = cube_mesh(1.0);
  const MeshDistance md(cube.positions, cube.triangles);
  EXPECT_EQ(md.edge_count(), 18u);  // 12 cube edges + 6 face diagonals
  // Hand values: centre −1; (0.5,0,0) is 0.5 from the face x = 1; (2,0,0) is 1 out;
  // (2,2,0) is √2 from the edge; (2,3,4) is |(1,2,3)| = √14 from the corner.
  EXPECT_NEAR(md.signed_distance(Vec3(0, 0, 0)).distance, -1.0, 1e-15);
  EXPECT_NEAR(md.signed_distance(Vec3(0.5, 0, 0)).distance, -0.5, 1e-15);
  EXPECT_NEAR(md.signed_distance(Vec3(2, 0, 0)).distance, 1.0, 1e-15);
  EXPECT_NEAR(md.signed_distance(Vec3(2, 2, 0)).distance, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(md.signed_distance(Vec3(2, 3, 4)).distance, std::sqrt(14.0), 1e-14);
  const SignedDistanceResult corner = md.signed_distance(Vec3(2, 3, 4));
  EXPECT_EQ(corner.feature, TriangleFeature::kVertex);
  EXPECT_EQ(corner.closest_point, Vec3(1, 1, 1));
  // The corner's angle-weighted pseudonormal is (1,1,1)/√3 by symmetry (each face meets the
  // corner with total angle π/2, whatever its triangulation).
  EXPECT_NEAR((corner.pseudonormal - Vec3(1, 1, 1).normalized()).norm(), 0.0, 1e-15);

  // Just inside and just outside (1e-6) near an edge and a corner, where the sign is decided by
  // the edge or vertex pseudonormal (a single face normal would get some of these wrong).
  for (const Real s : {1.0, -1.0}) {
    const Real off = 1.0 + s * 1e-6;
    EXPECT_NEAR(md.signed_distance(Vec3(off, off, 0.3)).distance, box_sdf(Vec3(off, off, 0.3), 1),
                1e-15);
    EXPECT_NEAR(md.signed_distance(Vec3(off, off, off)).distance, box_sdf(Vec3(off, off, off), 1),
                1e-15);
    EXPECT_EQ(md.signed_distance(Vec3(off, off, off)).distance > 0, s > 0);
  }

  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-2.5, 2.5);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const SignedDistanceResult r = md.signed_distance(p);
    EXPECT_NEAR(r.distance, box_sdf(p, 1.0), 1e-14) << p.transpose();
    EXPECT_NEAR((p - r.closest_point).norm(), std::abs(r.distance), 1e-14);
  }
}

TEST(MeshDistance, IcosphereMatchesTheSphereWithinTheTessellationError) {
  const auto sphere = sphere_mesh(3, 1.0);  // 1280 triangles
  ASSERT_EQ(sphere.triangles.size(), 1280u);
  const MeshDistance md(sphere.positions, sphere.triangles);
  // The mesh lies between the sphere of radius 1 (vertices) and that of the smallest distance
  // from the centre to a face plane, r_in; so for any p, |p| − 1 ≤ sd(p) ≤ |p| − r_in.
  Real r_in = 1;
  for (const Triangle& t : sphere.triangles) {
    const Vec3& a = sphere.positions[t[0]];
    const Vec3 n = (sphere.positions[t[1]] - a).cross(sphere.positions[t[2]] - a).normalized();
    r_in = std::min(r_in, std::abs(n.dot(a)));
  }
  EXPECT_GT(r_in, 0.99);  // level 3 icosphere: r_in ≈ 0.9949 (hand-checked order of magnitude)
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<Real> u(-2, 2);
  int inside = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Real d = md.signed_distance(p).distance;
    EXPECT_GE(d, p.norm() - 1 - 1e-12) << p.transpose();
    EXPECT_LE(d, p.norm() - r_in + 1e-12) << p.transpose();
    if (p.norm() < r_in) {
      EXPECT_LT(d, 0);
      ++inside;
    }
    if (p.norm() > 1) {
      EXPECT_GT(d, 0);
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_NEAR(md.signed_distance(Vec3::Zero()).distance, -r_in, 1e-12);
}

void expect_tree_matches_brute_force(const MeshDistance& md, std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> u(-2, 2);
  int sign_checked = 0;
  for (int i = 0; i < count; ++i) {
    // Half the points near the surface (within ±0.05 of a random vertex) to stress ties.
    Vec3 p(u(rng), u(rng), u(rng));
    if (i % 2 == 1) {
      const auto v = static_cast<std::size_t>(rng() % md.positions().size());
      p = md.positions()[v] + 0.025 * Vec3(u(rng), u(rng), u(rng));
    }
    const SignedDistanceResult t = md.signed_distance(p);
    const SignedDistanceResult b = md.signed_distance_brute_force(p);
    ASSERT_NEAR(std::abs(t.distance), std::abs(b.distance), 1e-14) << p.transpose();
    if (std::abs(b.distance) > 1e-9) {
      ASSERT_EQ(t.distance > 0, b.distance > 0) << p.transpose();
      ++sign_checked;
    }
  }
  EXPECT_GT(sign_checked, count * 9 / 10);
}

TEST(MeshDistance, TreeQueryEqualsBruteForceAndSurvivesRefit) {
  auto sphere = sphere_mesh(3, 1.0);
  MeshDistance md(sphere.positions, sphere.triangles);
  expect_tree_matches_brute_force(md, 5, 10000);

  // Deform: stretch x by 1.6, squash z, add a bump; the mesh stays closed and star-shaped.
  for (Vec3& p : sphere.positions) {
    p = Vec3(1.6 * p.x(), p.y(), 0.7 * p.z()) * (1.0 + 0.2 * std::sin(3 * p.x()) * p.y());
  }
  md.refit(sphere.positions);
  expect_tree_matches_brute_force(md, 6, 10000);
  // The refitted object answers like one built from the moved positions.
  const MeshDistance fresh(sphere.positions, sphere.triangles);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<Real> u(-2, 2);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    ASSERT_EQ(md.signed_distance(p).distance, fresh.signed_distance(p).distance);
  }
  // Points along the stretched x axis: inside up to x ≈ 1.6 (the bump is 0 at y = 0).
  EXPECT_LT(md.signed_distance(Vec3(1.5, 0, 0)).distance, 0);
  EXPECT_GT(md.signed_distance(Vec3(1.7, 0, 0)).distance, 0);
}

// The stretched, bumped icosphere of the refit test: closed, no symmetry left to hide errors.
TriMesh bumped_sphere() {
  auto sphere = sphere_mesh(3, 1.0);
  for (Vec3& p : sphere.positions) {
    p = Vec3(1.6 * p.x(), p.y(), 0.7 * p.z()) * (1.0 + 0.2 * std::sin(3 * p.x()) * p.y());
  }
  return sphere;
}

Vec3 unit_or_zero(const Vec3& v) { return v.norm() > 0 ? Vec3(v / v.norm()) : Vec3::Zero(); }

// MeshDistance computes pseudonormals on demand; they must be the very bits of the classic
// sweep that accumulates Σ α·n (vertices) and Σ n (edges) over all triangles in order.
TEST(MeshDistance, OnDemandPseudonormalsEqualTheSweepOverAllTriangles) {
  const TriMesh mesh = bumped_sphere();
  MeshDistance md(sphere_mesh(3, 1.0).positions, mesh.triangles);
  md.refit(mesh.positions);  // also checks that refit() leaves nothing stale
  std::vector<Vec3> vertex(mesh.positions.size(), Vec3::Zero());
  std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> edge;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3& a = mesh.positions[tri[0]];
    const Vec3 n = unit_or_zero((mesh.positions[tri[1]] - a).cross(mesh.positions[tri[2]] - a));
    ASSERT_EQ(md.face_normal(static_cast<std::uint32_t>(t)), n);
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3& p = mesh.positions[tri[k]];
      const Vec3 u = mesh.positions[tri[(k + 1) % 3]] - p;
      const Vec3 v = mesh.positions[tri[(k + 2) % 3]] - p;
      vertex[tri[k]] += std::atan2(u.cross(v).norm(), u.dot(v)) * n;
      const std::uint32_t b = tri[(k + 1) % 3];
      edge.try_emplace({std::min(tri[k], b), std::max(tri[k], b)}, Vec3::Zero()).first->second += n;
    }
  }
  for (std::size_t v = 0; v < vertex.size(); ++v) {
    ASSERT_EQ(md.vertex_pseudonormal(static_cast<std::uint32_t>(v)), unit_or_zero(vertex[v])) << v;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[t][static_cast<std::size_t>(k)];
      const std::uint32_t b = mesh.triangles[t][static_cast<std::size_t>((k + 1) % 3)];
      ASSERT_EQ(md.edge_pseudonormal(static_cast<std::uint32_t>(t), k),
                unit_or_zero(edge.at({std::min(a, b), std::max(a, b)})));
    }
  }
  EXPECT_EQ(md.edge_count(), edge.size());
}

// A hint (any triangle, near or far, or none) changes the work, never the distance.
TEST(MeshDistance, HintedQueriesGiveTheSameDistance) {
  const TriMesh mesh = bumped_sphere();
  const MeshDistance md(mesh.positions, mesh.triangles);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-2, 2);
  std::uint32_t previous = MeshDistance::kNoTriangle;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const SignedDistanceResult plain = md.signed_distance(p);
    const auto random = static_cast<std::uint32_t>(rng() % mesh.triangles.size());
    for (const std::uint32_t hint : {plain.triangle, random, previous, MeshDistance::kNoTriangle}) {
      ASSERT_EQ(md.signed_distance(p, hint).distance, plain.distance) << p.transpose();
    }
    previous = plain.triangle;
  }
}

// A batch query gives every point its own query's distance, whatever the hints, and leaves the
// nearest triangle in the hint; batches of clustered and of scattered points.
TEST(MeshDistance, BatchQueriesEqualSingleQueries) {
  const TriMesh mesh = bumped_sphere();
  MeshDistance md(sphere_mesh(3, 1.0).positions, mesh.triangles);
  md.refit(mesh.positions);
  MeshDistance::BatchScratch scratch(mesh.triangles.size());
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int batch = 0; batch < 400; ++batch) {
    const Real spread = batch % 2 == 0 ? 0.05 : 2.0;  // a cluster near the surface, or anywhere
    const Vec3 centre = mesh.positions[rng() % mesh.positions.size()];
    std::vector<Vec3> points(1 + rng() % 16);
    std::vector<std::uint32_t> hints(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      points[k] = centre + spread * Vec3(u(rng), u(rng), u(rng));
      const std::uint64_t pick = rng() % 3;  // none, a random triangle, or the right one
      hints[k] = pick == 0   ? MeshDistance::kNoTriangle
                 : pick == 1 ? static_cast<std::uint32_t>(rng() % mesh.triangles.size())
                             : md.signed_distance(points[k]).triangle;
    }
    std::vector<SignedDistanceResult> results(points.size());
    md.signed_distances(points, hints, results, scratch);
    for (std::size_t k = 0; k < points.size(); ++k) {
      const SignedDistanceResult single = md.signed_distance(points[k]);
      ASSERT_EQ(results[k].distance, single.distance) << points[k].transpose();
      ASSERT_EQ(hints[k], results[k].triangle);
      ASSERT_NEAR((points[k] - results[k].closest_point).norm(), std::abs(single.distance), 1e-15);
    }
  }
}

TEST(MeshDistance, RejectsBadInputAndHandlesEmptyMeshes) {
  const std::vector<Vec3> pts = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::vector<Triangle> bad = {{0, 1, 3}};
  EXPECT_THROW(MeshDistance(pts, bad), Error);
  const MeshDistance empty(pts, {});
  const SignedDistanceResult r = empty.signed_distance(Vec3(1, 2, 3));
  EXPECT_EQ(r.triangle, MeshDistance::kNoTriangle);
  EXPECT_TRUE(std::isinf(r.distance));
  MeshDistance::BatchScratch scratch(1);
  std::vector<SignedDistanceResult> results(2);
  results[1].distance = 1;
  std::vector<std::uint32_t> hints = {MeshDistance::kNoTriangle, 5};
  empty.signed_distances(std::span(pts).first(2), hints, results, scratch);
  for (const SignedDistanceResult& b : results) EXPECT_EQ(b.triangle, MeshDistance::kNoTriangle);
  EXPECT_TRUE(std::isinf(results[1].distance));
  EXPECT_EQ(hints[1], MeshDistance::kNoTriangle);
  MeshDistance one(pts, std::vector<Triangle>{{0, 1, 2}});
  MeshDistance::BatchScratch too_small(0);
  EXPECT_THROW(one.signed_distances(std::span(pts).first(1), std::span(hints).first(1),
                                    std::span(results).first(1), too_small),
               Error);
  EXPECT_THROW(one.refit(std::vector<Vec3>(2)), Error);
  // A single triangle: above its normal side positive.
  EXPECT_NEAR(one.signed_distance(Vec3(0.2, 0.2, 0.5)).distance, 0.5, 1e-15);
  EXPECT_NEAR(one.signed_distance(Vec3(0.2, 0.2, -0.5)).distance, -0.5, 1e-15);
}

}  // namespace
}  // namespace trocar
