// Property tests on 10^5 random intersecting instrument/tissue triangle pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "trocar/geometry/closest_point.h"
#include "trocar/geometry/triangle_triangle.h"
#include "trocar/response/response_solver.h"

namespace trocar {
namespace {

struct RandomPair {
  std::array<Vec3, 3> a, b;
  Real size = 1;  // L: the pair's size (largest bounding-box side)
};

// B: random triangle of size ~scale around c; A: three points around a random point of B, kept
// when the triangles intersect and are not coplanar (the detector's contacts).
RandomPair random_pair(std::mt19937& rng) {
  std::uniform_real_distribution<Real> u(-1, 1), u01(0, 1), lg(-3, 0);
  for (;;) {
    const Real scale = std::pow(10.0, lg(rng));
    const Vec3 c(u(rng), u(rng), u(rng));
    RandomPair p;
    for (Vec3& x : p.b) x = c + scale * Vec3(u(rng), u(rng), u(rng));
    Real w0 = u01(rng), w1 = u01(rng);
    if (w0 + w1 > 1) {
      w0 = 1 - w0;
      w1 = 1 - w1;
    }
    const Vec3 x = p.b[0] + w0 * (p.b[1] - p.b[0]) + w1 * (p.b[2] - p.b[0]);
    for (Vec3& y : p.a) y = x + 0.7 * scale * Vec3(u(rng), u(rng), u(rng));
    const TriTriResult r = intersect_triangles(p.a[0], p.a[1], p.a[2], p.b[0], p.b[1], p.b[2]);
    if (!r.intersects || r.coplanar) continue;
    Aabb box;
    for (int i = 0; i < 3; ++i) {
      box.expand(p.a[i]);
      box.expand(p.b[i]);
    }
    p.size = box.size().maxCoeff();
    return p;
  }
}

Real dist_to_triangle(const Vec3& x, const std::array<Vec3, 3>& t) {
  return (closest_point_on_triangle(x, t[0], t[1], t[2]).point - x).norm();
}

TEST(ResponseProperties, RandomPairs) {
  constexpr int kPairs = 100000;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<Real> u(-1, 1);
  ResponseSettings s;
  s.method = ResponseMethod::kObb;  // the seed's kernel (the default is sdf)
  s.pierce_filter = false;  // random orientations: the top vertex means nothing here
  s.max_force = 0;
  ResponseSolver solver(s);
  solver.reset(3);
  TissueLoads loads;
  loads.reset(3, 4);
  const std::vector<Triangle> tissue_tri{{0, 1, 2}};
  int applied = 0, missed = 0;
  Real worst_on_a = 0, worst_on_b = 0;
  for (int k = 0; k < kPairs; ++k) {
    const RandomPair p = random_pair(rng);
    // The instrument: A plus three points around it (a 3-D box), moved rigidly from a random
    // earlier pose so it has a random linear and angular velocity, arriving with world = local.
    TriMesh mesh;
    mesh.positions = {p.a[0], p.a[1], p.a[2]};
    for (int i = 0; i < 3; ++i) mesh.positions.push_back(p.a[i] + 0.3 * p.size * Vec3(u(rng), u(rng), u(rng)));
    mesh.triangles = {{0, 1, 2}};
    Instrument tool(std::move(mesh));
    Pose before;
    before.translation = 1e-3 * p.size * Vec3(u(rng), u(rng), u(rng));
    before.rotation = Quat(Eigen::AngleAxis<Real>(1e-3 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    tool.reset_pose(before);
    tool.move_to(Pose::identity(), 1e-3);
    const std::vector<Vec3> tissue_x{p.b[0], p.b[1], p.b[2]};
    const std::vector<Vec3> tissue_v{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)),
                                     Vec3(u(rng), u(rng), u(rng))};
    Contact c;
    c.object_a = 0;
    c.object_b = 1;
    loads.clear();
    InstrumentLoad load;
    const ResponseStats st =
        solver.apply({&c, 1}, 0, 1, tool, TissueView{tissue_x, tissue_v, tissue_tri}, loads, load);
    if (st.count(ContactStatus::kApplied) != 1) {
      missed += st.count(ContactStatus::kMissed);
      continue;
    }
    ++applied;
    const ContactResponse& r = solver.last();
    // P lies on both triangles (relative to the pair's size).
    worst_on_a = std::max(worst_on_a, dist_to_triangle(r.point, p.a) / p.size);
    worst_on_b = std::max(worst_on_b, dist_to_triangle(r.point, p.b) / p.size);
    // The tissue force never points out of the tissue: F·n_out ≤ 0.
    const Vec3 n_out = (p.b[1] - p.b[0]).cross(p.b[2] - p.b[0]).normalized();
    ASSERT_LE(r.force.dot(n_out), 0.0);
    ASSERT_TRUE(r.force.allFinite());
    // The instrument's force is exactly opposite the tissue's total, with torque (P − o) × (−F).
    const Vec3 tissue_total = loads.forces()[0] + loads.forces()[1] + loads.forces()[2];
    ASSERT_LE((load.raw_force + tissue_total).norm(), 1e-12 * r.force.norm() + 1e-300);
    ASSERT_LE((load.raw_torque - r.point.cross(load.raw_force)).norm(),
              1e-12 * r.force.norm() * (r.point.norm() + 1) + 1e-300);
  }
  EXPECT_LE(worst_on_a, 1e-9);
  EXPECT_LE(worst_on_b, 1e-9);
  // Every intersecting, non-coplanar pair gets a force except rounding-size misses.
  EXPECT_GE(applied, kPairs - kPairs / 1000) << "missed " << missed;
  std::printf("applied %d of %d, worst distance of P to A %.2e, to B %.2e (relative)\n", applied, kPairs,
              worst_on_a, worst_on_b);
}

TEST(ResponseProperties, ForceGrowsWithDepth) {
  // Push the same instrument triangle (and its box) deeper along n_in in steps of 1% of the
  // pair's size while the pair still intersects: |F| never decreases. Motion along n_in (the
  // push) at a random speed, or at rest: then |D| = PD·n_in = (box support along n_in) −
  // n_in·(P − c), which grows exactly by the step since P stays on the tissue plane.
  constexpr int kPairs = 100000;
  std::mt19937 rng(77);
  std::uniform_real_distribution<Real> u(-1, 1), u01(0, 1);
  ResponseSettings s;
  s.method = ResponseMethod::kObb;  // the seed's kernel (the default is sdf)
  s.pierce_filter = false;
  long checked = 0;
  for (int k = 0; k < kPairs; ++k) {
    RandomPair p = random_pair(rng);
    std::vector<Vec3> pts(p.a.begin(), p.a.end());
    for (int i = 0; i < 3; ++i) pts.push_back(p.a[i] + 0.3 * p.size * Vec3(u(rng), u(rng), u(rng)));
    Obb box = Obb::fit_pca(pts);
    const Vec3 n_in = -(p.b[1] - p.b[0]).cross(p.b[2] - p.b[0]).normalized();
    const Real speed = (k % 2 == 0) ? 0.0 : u01(rng);
    ContactTriangles t;
    t.b = p.b;
    t.vb = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    t.va = {speed * n_in, speed * n_in, speed * n_in};
    Real previous = -1;
    for (int step = 0; step < 10; ++step) {
      const Vec3 shift = (0.01 * p.size * step) * n_in;
      for (int i = 0; i < 3; ++i) t.a[i] = p.a[i] + shift;
      const TriTriResult tt = intersect_triangles(t.a[0], t.a[1], t.a[2], t.b[0], t.b[1], t.b[2]);
      if (!tt.intersects || tt.coplanar) break;
      Obb moved = box;
      moved.center += shift;
      const ContactResponse r = respond_contact(t, moved, nullptr, {}, s);
      if (r.status != ContactStatus::kApplied) break;
      const Real f = r.force.norm();
      ASSERT_GE(f, previous - 1e-9 * s.stiffness * p.size) << "pair " << k << " step " << step;
      previous = f;
      ++checked;
    }
  }
  EXPECT_GT(checked, 2 * kPairs);
}

}  // namespace
}  // namespace trocar
