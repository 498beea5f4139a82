// Tissue against tissue (docs/response.md, "Tissue against tissue"): the prosthetic mesh on a
// curved deformable wall, the rolled mesh unrolling without crossing itself, and tacks that hold
// below their pull-out force and tear above it. The checks use their own geometry (closest
// points by brute force, segment–triangle crossings), not the solver's grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/geometry/closest_point.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/prosthetic_mesh.h"
#include "trocar/mesh/validate.h"
#include "trocar/response/tissue_contact.h"
#include "trocar/response/xpbd_coupling.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/material.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {
namespace {

constexpr Real kDt = 1e-3;
const Vec3 kGravity(0, 0, -9.81);

/// How the tests below solve contacts and tacks: after the integrators (implicit Euler tissues,
/// TissueContactSolver::solve) or inside the substeps of XPBD tissues stepped in lock-step
/// (step_coupled). The tests that run both are TEST_P over it.
enum class Solve { kAfter, kCoupled };
Solve g_solve = Solve::kAfter;

/// One tissue stepped by hand (what Simulation::deform does, without instruments).
struct Body {
  MassSpringSettings settings;
  MassSpringState state;
  std::unique_ptr<MassSpringIntegrator> integrator;
  TissueLoads loads;
  Body(const TriMesh& mesh, const MassSpringMaterial& m, const FixedSelection& fixed = {}, const Vec3& gravity = kGravity)
      : settings(MassSpringSettings::build(mesh, m, fixed, gravity)), state(MassSpringState::at_rest(settings)) {
    integrator = std::make_unique<MassSpringIntegrator>(
        settings, g_solve == Solve::kCoupled ? IntegratorKind::kXpbd : IntegratorKind::kImplicitEuler);
    loads.reset(settings.vertex_count());
  }
};

/// `bodies` in the solver's tissue order.
void step(std::vector<Body*> bodies, TissueContactSolver& solver, Real time) {
  solver.begin_step();
  if (g_solve == Solve::kCoupled) {
    std::vector<CoupledTissue> coupled;
    int substeps = 1;
    for (Body* b : bodies) {
      coupled.push_back({b->integrator->xpbd(), &b->state, &b->loads, nullptr});
      substeps = std::max(substeps, b->integrator->xpbd()->options().substeps);
    }
    std::vector<XpbdStats> stats(bodies.size());
    step_coupled(coupled, solver, kDt, substeps, time, stats);
    return;
  }
  for (Body* b : bodies) b->integrator->step(b->state, b->loads, kDt);
  solver.solve(kDt, time);
}

/// The tests that hold for both ways of solving.
class TissueContactBoth : public ::testing::TestWithParam<Solve> {
 protected:
  void SetUp() override { g_solve = GetParam(); }
  void TearDown() override { g_solve = Solve::kAfter; }
};
INSTANTIATE_TEST_SUITE_P(, TissueContactBoth, ::testing::Values(Solve::kAfter, Solve::kCoupled),
                         [](const ::testing::TestParamInfo<Solve>& solve) {
                           return solve.param == Solve::kAfter ? "AfterTheIntegrators" : "InsideXpbdSubsteps";
                         });

/// The point `where` on b's surface (tissue index `tissue`): the last triangle it lies on (within
/// 1 nm; a vertex lies on several), or the default point when it lies on none.
SurfacePoint surface_point_at(const Body& b, std::uint32_t tissue, const Vec3& where) {
  SurfacePoint found;
  for (std::uint32_t t = 0; t < b.settings.triangles.size(); ++t) {
    const Triangle& tri = b.settings.triangles[t];
    const TriangleClosestPoint q = closest_point_on_triangle(where, b.state.positions[tri[0]], b.state.positions[tri[1]],
                                                             b.state.positions[tri[2]]);
    if ((q.point - where).norm() < 1e-9) found = {tissue, t, q.barycentric};
  }
  return found;
}

/// Signed distance of p from the surface (brute force over every triangle; the sign from the
/// nearest triangle's normal).
Real signed_distance_brute(const Vec3& p, const MassSpringSettings& s, const std::vector<Vec3>& x) {
  Real best = std::numeric_limits<Real>::infinity(), sign = 1;
  for (const Triangle& t : s.triangles) {
    const TriangleClosestPoint q = closest_point_on_triangle(p, x[t[0]], x[t[1]], x[t[2]]);
    const Real d = (p - q.point).norm();
    if (d < best) {
      best = d;
      const Vec3 n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
      sign = n.dot(p - q.point) >= 0 ? 1 : -1;
    }
  }
  return sign * best;
}

/// A sheet bent onto a cylinder of radius R about the y axis, crown at z = 0, normals outward.
TriMesh curved_wall(Real R) {
  TriMesh m = make_sheet(0.2, 0.16, 25, 20);
  for (Vec3& p : m.positions) p = Vec3(R * std::sin(p.x() / R), p.y(), R * std::cos(p.x() / R) - R);
  return m;
}

struct RestOutcome {
  Real min_distance = 0;   ///< the lowest mesh vertex's signed distance from the wall (m)
  Real p99_shortfall = 0;  ///< 99th percentile of max(0, thickness − distance) (m)
  Real max_speed = 0;      ///< the fastest mesh vertex at the end (m/s)
};

RestOutcome mesh_on_wall(Real spacing, Real mass_scale, Real wall_scale, bool self_contact) {
  constexpr Real kThickness = 1e-3;
  MassSpringMaterial wm = material_preset("peritoneum");
  wm.sheet_thickness = 0.003;
  wm.k_structural *= 5 * wall_scale;
  wm.k_bending *= 5 * wall_scale;
  wm.k_home = 20 * wall_scale;
  wm.k_area = 5 * wall_scale;
  FixedSelection border;
  border.below_plane = Plane{Vec3(0, 0, -0.03), Vec3(0, 0, -1)};  // the wall's far edges
  Body wall(curved_wall(0.15), wm, border);
  MassSpringMaterial mm = material_preset("polypropylene-mesh");
  mm.density *= mass_scale;
  TriMesh sheet = make_prosthetic_mesh(0.08, 0.06, spacing);
  for (Vec3& p : sheet.positions) p.z() += 0.004;
  Body mesh(sheet, mm);
  std::vector<TissueContactPair> pairs{{1, 0, kThickness, 0.3}};
  if (self_contact) pairs.push_back({1, 1, kThickness, 0.3});
  TissueContactSolver solver({{&wall.settings, &wall.state}, {&mesh.settings, &mesh.state}}, pairs);
  RestOutcome out;
  out.min_distance = std::numeric_limits<Real>::infinity();
  const int steps = 1500;
  for (int n = 1; n <= steps; ++n) {
    step({&wall, &mesh}, solver, n * kDt);
    if (n % 100 == 0 || n == steps)  // never below the wall, while falling and at rest
      for (const Vec3& p : mesh.state.positions)
        out.min_distance = std::min(out.min_distance, signed_distance_brute(p, wall.settings, wall.state.positions));
  }
  std::vector<Real> shortfall;
  for (const Vec3& p : mesh.state.positions) {
    const Real d = signed_distance_brute(p, wall.settings, wall.state.positions);
    shortfall.push_back(std::max<Real>(0, kThickness - d));
  }
  std::sort(shortfall.begin(), shortfall.end());
  out.p99_shortfall = shortfall[static_cast<std::size_t>(0.99 * static_cast<Real>(shortfall.size() - 1))];
  for (const Vec3& v : mesh.state.velocities) out.max_speed = std::max(out.max_speed, v.norm());
  return out;
}

TEST_P(TissueContactBoth, MeshRestsOnACurvedDeformableWall) {
  const RestOutcome r = mesh_on_wall(0.005, 1, 1, true);
  std::printf("mesh on wall (5 mm, nominal): min distance %.3f mm, p99 shortfall %.4f mm, max speed %.2g m/s\n",
              1e3 * r.min_distance, 1e3 * r.p99_shortfall, r.max_speed);
  EXPECT_GT(r.min_distance, 0);
  EXPECT_LE(r.p99_shortfall, 0.5e-3);
  // Not asserted: the fastest vertex still moves ~0.17 m/s at 1.5 s (a free edge of the stiff,
  // light knit; not yet looked into).
}

TEST_P(TissueContactBoth, MeshRestsOnTheWallInEveryCellOfTheGrid) {
  Real worst_p99 = 0, worst_min = std::numeric_limits<Real>::infinity();
  char worst[96] = "";
  for (const Real spacing : {0.004, 0.008})
    for (const Real mass : {0.5, 2.0})
      for (const Real wall : {0.5, 2.0}) {
        const RestOutcome r = mesh_on_wall(spacing, mass, wall, false);
        EXPECT_GT(r.min_distance, 0) << spacing << " " << mass << " " << wall;
        EXPECT_LE(r.p99_shortfall, 0.5e-3) << spacing << " " << mass << " " << wall;
        worst_min = std::min(worst_min, r.min_distance);
        if (r.p99_shortfall >= worst_p99) {
          worst_p99 = r.p99_shortfall;
          std::snprintf(worst, sizeof worst, "spacing %.0f mm, mass x%.1f, wall x%.1f", 1e3 * spacing, mass, wall);
        }
      }
  std::printf("worst cell: %s: p99 shortfall %.4f mm; lowest vertex over the grid %.3f mm above the wall\n", worst,
              1e3 * worst_p99, 1e3 * worst_min);
}

// Adhesion holds a vertex through the face beneath it, not through an edge beyond which it lies:
// an open sheet's rim (the defect's) pulling every vertex within range toward its nearest edge
// drew a mesh laid over the hole in from all sides until the contacts fed one another and it flew
// apart (the TAPP groin, 10 steps after the start).
TEST(TissueContact, AdhesionHoldsThroughTheFaceBeneathAVertexOnly) {
  const auto separating_speed_after = [](const Vec3& offset) {
    TriMesh floor_mesh;  // one fixed triangle, normal +z
    floor_mesh.positions = {Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0, 0.01, 0)};
    floor_mesh.triangles = {Triangle{0, 1, 2}};
    FixedSelection all;
    all.below_plane = Plane{Vec3(0, 0, 1), Vec3(0, 0, 1)};
    MassSpringSettings fs = MassSpringSettings::build(floor_mesh, MassSpringMaterial{}, all);
    MassSpringState fx = MassSpringState::at_rest(fs);
    TriMesh probe;  // vertex 0 near the floor, the others far out of range
    probe.positions = {offset, offset + Vec3(0, 0, 0.02), offset + Vec3(0.002, 0, 0.02)};
    probe.triangles = {Triangle{0, 1, 2}};
    MassSpringSettings ps = MassSpringSettings::build(probe, MassSpringMaterial{});
    MassSpringState px = MassSpringState::at_rest(ps);
    TissueContactPair pair{1, 0, 0.001, 0};
    pair.adhesion = 20;  // 0.02 m/s per 1 ms step
    TissueContactSolver solver({{&fs, &fx}, {&ps, &px}}, {pair});
    solver.begin_step();
    for (Vec3& v : px.velocities) v = Vec3(0, 0, 0.05);  // leaving the floor at 5 cm/s
    solver.solve(kDt, kDt);
    return px.velocities[0].z();
  };
  // 1.8 mm above the face (0.8 mm beyond the 1 mm gap): adhesion takes 0.02 m/s off.
  EXPECT_NEAR(separating_speed_after(Vec3(0.002, 0.002, 0.0018)), 0.05 - 20 * kDt, 1e-9);
  // 1.8 mm from the triangle's edge x = 0, beyond it (not over the face): untouched.
  EXPECT_DOUBLE_EQ(separating_speed_after(Vec3(-0.0018 / std::sqrt(2.0), 0.005, 0.0018 / std::sqrt(2.0))), 0.05);
}

/// A fixed sheet (two triangles left of the line x = 0, one right of it, normals +z when flat) and
/// a probe triangle whose vertex 0 comes near it: the sheet and the probe go from their start
/// positions to their end positions in one step; the solve after the integrators then corrects
/// them. Returns where the probe's vertex 0 ends (m).
Vec3 probe_after_one_step(const std::vector<Vec3>& sheet_start, const std::vector<Vec3>& sheet_end,
                          const Vec3& probe_start, const Vec3& probe_end) {
  TriMesh sheet;
  sheet.positions = sheet_start;
  sheet.triangles = {Triangle{0, 1, 2}, Triangle{0, 2, 3}, Triangle{1, 4, 2}};
  FixedSelection all;
  all.below_plane = Plane{Vec3(0, 0, 1), Vec3(0, 0, 1)};
  MassSpringSettings ss = MassSpringSettings::build(sheet, MassSpringMaterial{}, all);
  MassSpringState sx = MassSpringState::at_rest(ss);
  TriMesh probe;  // vertex 0 near the sheet, the others 2 cm above it
  probe.positions = {probe_start, probe_start + Vec3(0, 0, 0.02), probe_start + Vec3(0.002, 0, 0.02)};
  probe.triangles = {Triangle{0, 1, 2}};
  MassSpringSettings ps = MassSpringSettings::build(probe, MassSpringMaterial{});
  MassSpringState px = MassSpringState::at_rest(ps);
  TissueContactSolver solver({{&ss, &sx}, {&ps, &px}}, {TissueContactPair{1, 0, 0.001, 0}});
  solver.begin_step();
  sx.positions = sheet_end;
  for (Vec3& v : px.positions) v += probe_end - probe_start;
  solver.solve(kDt, kDt);
  return px.positions[0];
}

// The side a vertex keeps of a sheet's plane decides only where it can have crossed the sheet. A
// vertex beside a fold, over the face next to it, lies beyond the folded triangle's plane without
// having crossed anything, and a vertex beside the sheet's rim can pass from one side of its plane
// to the other around the rim; pulled back to the remembered side, either was flung by the gap
// plus its distance (the novice's dropped mesh blew up so, docs/procedure.md). A vertex that goes
// through the fold line itself is still pushed back.
TEST(TissueContact, TheSideOfASheetHoldsOnlyWhereAVertexCanHaveCrossedIt) {
  const std::vector<Vec3> flat = {Vec3(-0.01, -0.005, 0), Vec3(0, -0.005, 0), Vec3(0, 0.005, 0), Vec3(-0.01, 0.005, 0),
                                  Vec3(0.01, 0, 0)};
  std::vector<Vec3> ridge = flat;  // the right triangle folded 60° down about x = 0
  ridge[4] = Vec3(0.005, 0, -0.01 * std::sin(M_PI / 3));
  // Rising from 0.5 to 1.2 mm over the left face (beyond the 1 mm gap), 0.9 mm beside the fold,
  // while the fold forms: the folded triangle's plane passes 1.56 mm above it, 1.5 mm from the
  // fold. Nothing to correct (with the side kept, it moved 2.5 mm).
  const Vec3 beside_fold(-0.0009, 0, 0.0012);
  EXPECT_NEAR((probe_after_one_step(flat, ridge, Vec3(-0.0009, 0, 0.0005), beside_fold) - beside_fold).norm(), 0,
              1e-12);

  // 0.9 mm beyond the sheet's rim (x = -1 cm), from 1 mm above its plane to 1 mm below: around
  // the rim, untouched (1.35 mm from it; with the side kept, it moved 2.5 mm).
  const Vec3 above_rim(-0.0109, 0, 0.001), below_rim(-0.0109, 0, -0.001);
  EXPECT_NEAR((probe_after_one_step(flat, flat, above_rim, below_rim) - below_rim).norm(), 0, 1e-12);

  // Through the fold line of a valley (the right triangle folded 30° up): from 1.5 mm above the
  // fold to 0.5 mm below it, beyond both triangles' edges. Pushed back over both faces (without
  // the side, on through).
  std::vector<Vec3> valley = flat;
  valley[4] = Vec3(0.01 * std::cos(M_PI / 6), 0, 0.01 * std::sin(M_PI / 6));
  const Vec3 end = probe_after_one_step(valley, valley, Vec3(0.0002, 0, 0.0015), Vec3(0.0002, 0, -0.0005));
  const Vec3 right_normal(-std::sin(M_PI / 6), 0, std::cos(M_PI / 6));
  EXPECT_GT(end.z(), 0.0008) << "over the left face, mm: " << end.z() * 1e3;
  EXPECT_GT(right_normal.dot(end), 0.0008) << "over the right face, mm: " << right_normal.dot(end) * 1e3;
}

/// Segment pq crosses triangle abc (Möller–Trumbore on the segment, endpoints included). Written
/// here on purpose, apart from geometry/segment_triangle.h: the solver's fail-safe uses that one,
/// and the check of its result must not share its mistakes.
bool crosses_by_hand(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const Real det = e1.dot(h);
  if (std::abs(det) < 1e-20) return false;
  const Real f = 1 / det;
  const Vec3 s = p - a;
  const Real u = f * s.dot(h);
  if (u < 0 || u > 1) return false;
  const Vec3 qv = s.cross(e1);
  const Real v = f * d.dot(qv);
  if (v < 0 || u + v > 1) return false;
  const Real t = f * e2.dot(qv);
  return t >= 0 && t <= 1;
}

/// Edge–triangle crossings within one surface, over edges and triangles that share no vertex, by
/// brute force (every edge against every triangle): the reference for self_crossings.
int self_crossings_brute(const MassSpringSettings& s, const std::vector<Vec3>& x) {
  int count = 0;
  for (std::size_t e = 0; e < s.structural_count; ++e) {
    const Spring& sp = s.springs[e];
    for (const Triangle& t : s.triangles) {
      if (t[0] == sp.i || t[1] == sp.i || t[2] == sp.i || t[0] == sp.j || t[1] == sp.j || t[2] == sp.j) continue;
      if (crosses_by_hand(x[sp.i], x[sp.j], x[t[0]], x[t[1]], x[t[2]])) ++count;
    }
  }
  return count;
}

/// The same count through a broad phase: the triangles' boxes binned in a uniform grid of `cell` (m) cubes (a box over
/// several cells is listed in each); an edge tests the triangles listed in the cells its box
/// covers, each pair once. Exact: every pair whose boxes overlap shares a cell.
int self_crossings(const MassSpringSettings& s, const std::vector<Vec3>& x, Real cell = 0.005) {
  const auto cell_of = [&](const Vec3& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell)), static_cast<int>(std::floor(p.y() / cell)),
                           static_cast<int>(std::floor(p.z() / cell)));
  };
  const auto key = [](int i, int j, int k) {
    return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
           (static_cast<std::int64_t>(k) * 83492791);
  };
  std::vector<Vec3> lo, hi;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
    const Triangle& tri = s.triangles[t];
    lo.push_back(x[tri[0]].cwiseMin(x[tri[1]]).cwiseMin(x[tri[2]]));
    hi.push_back(x[tri[0]].cwiseMax(x[tri[1]]).cwiseMax(x[tri[2]]));
    const Eigen::Vector3i a = cell_of(lo.back()), b = cell_of(hi.back());
    if (((b - a).array() > 64).any()) return self_crossings_brute(s, x);  // torn apart: no grid
    for (int i = a.x(); i <= b.x(); ++i)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int k = a.z(); k <= b.z(); ++k) grid[key(i, j, k)].push_back(t);
  }
  std::vector<std::uint32_t> seen(s.triangles.size(), std::numeric_limits<std::uint32_t>::max());
  int count = 0;
  for (std::uint32_t e = 0; e < s.structural_count; ++e) {
    const Spring& sp = s.springs[e];
    const Vec3 &p = x[sp.i], &q = x[sp.j];
    const Vec3 elo = p.cwiseMin(q), ehi = p.cwiseMax(q);
    const Eigen::Vector3i a = cell_of(elo), b = cell_of(ehi);
    if (((b - a).array() > 64).any()) return self_crossings_brute(s, x);
    for (int i = a.x(); i <= b.x(); ++i)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int k = a.z(); k <= b.z(); ++k) {
          const auto found = grid.find(key(i, j, k));
          if (found == grid.end()) continue;
          for (const std::uint32_t t : found->second) {
            if (seen[t] == e) continue;  // met in an earlier cell of this edge
            seen[t] = e;
            const Triangle& tri = s.triangles[t];
            if (tri[0] == sp.i || tri[1] == sp.i || tri[2] == sp.i || tri[0] == sp.j || tri[1] == sp.j ||
                tri[2] == sp.j)
              continue;
            if ((elo.array() > hi[t].array()).any() || (ehi.array() < lo[t].array()).any()) continue;
            if (crosses_by_hand(p, q, x[tri[0]], x[tri[1]], x[tri[2]])) ++count;
          }
        }
  }
  return count;
}

// The roll opens under its bending springs without crossing itself, to about half its width:
// springs across two edges barely drive the gentle outer turn (the rest is the graspers' work).
// At 1.5 N/m it opens furthest; RolledMeshGrid below runs the whole measured grid.
TEST(TissueContact, RolledMeshOpensWithoutCrossingItself) {
  constexpr Real kWidth = 0.08;
  TriMesh floor_mesh = make_sheet(0.3, 0.2, 6, 4);
  FixedSelection all;
  for (std::uint32_t v = 0; v < floor_mesh.vertex_count(); ++v) all.indices.push_back(v);
  Body floor(floor_mesh, material_preset("peritoneum"), all);
  TriMesh sheet = make_prosthetic_mesh(kWidth, 0.05, 0.005);
  for (Vec3& p : sheet.positions) p.z() += 0.0015;
  MassSpringMaterial knit = material_preset("polypropylene-mesh");
  knit.k_bending = 1.5;
  Body mesh(sheet, knit);
  roll_sheet(mesh.state.positions, SheetRoll{1, 0.004, 0.003});
  ASSERT_EQ(self_crossings(mesh.settings, mesh.state.positions), 0);
  ASSERT_EQ(self_crossings_brute(mesh.settings, mesh.state.positions), 0);
  const auto extent = [&] {
    Real lo = 1, hi = -1;
    for (const Vec3& p : mesh.state.positions) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
    return hi - lo;
  };
  const Real rolled = extent();
  TissueContactSolver solver({{&floor.settings, &floor.state}, {&mesh.settings, &mesh.state}},
                             {{1, 0, 1e-3, 0.3}, {1, 1, 1e-3, 0.3}});
  int crossings = 0, first_crossing = -1, steps_run = 0;
  const int steps = 2000;
  for (int n = 1; n <= steps; ++n) {
    step({&floor, &mesh}, solver, n * kDt);
    steps_run = n;
    // A crossed state persists (the side memory keeps it), so every 5th step and the last see it.
    if (n % 5 != 0 && n != steps) continue;
    const int c = self_crossings(mesh.settings, mesh.state.positions);
    if (c > 0) {  // the first crossed state: the test has failed; stop before it tangles further
      crossings = c;
      first_crossing = n;
      break;
    }
  }
  EXPECT_EQ(self_crossings(mesh.settings, mesh.state.positions),
            self_crossings_brute(mesh.settings, mesh.state.positions));  // the grid misses nothing
  const Real unrolled = extent();
  std::printf("roll: x extent %.1f mm rolled, %.1f mm after %d steps (flat %.0f mm); crossings %d (first at step %d)\n",
              1e3 * rolled, 1e3 * unrolled, steps_run, 1e3 * kWidth, crossings, first_crossing);
  EXPECT_EQ(crossings, 0);
  EXPECT_GT(unrolled, 2 * rolled) << "it opens";
  EXPECT_GT(unrolled, 0.4 * kWidth);
}

/// Two triangles of one tissue, 2 cm on a side, facing across a right angle: A hangs in the
/// plane y = 0 from its top edge e, (−1, 0, 0)–(1, 0, 0) cm; B stands in the plane x = 0 on its
/// bottom edge f, (0, −1, h)–(0, 1, h) cm. The edges cross over each other at x = y = 0, h apart
/// in z; no vertex is near the other triangle (each is 1 cm or more from it). Weightless in space,
/// equal vertex masses (equal areas). `fixed`: every vertex fixed.
Body crossed_edges(Real h, bool fixed = false) {
  TriMesh two;
  two.positions = {Vec3(-0.01, 0, 0), Vec3(0.01, 0, 0), Vec3(0, 0, -0.02),
                   Vec3(0, -0.01, h),  Vec3(0, 0.01, h), Vec3(0, 0, h + 0.02)};
  two.triangles = {Triangle{0, 1, 2}, Triangle{3, 4, 5}};
  FixedSelection none, all;
  all.indices = {0, 1, 2, 3, 4, 5};
  return Body(two, material_preset("polypropylene-mesh"), fixed ? all : none, Vec3::Zero());
}

/// The height of f over e where they cross (z of f's point over the origin minus e's).
Real edge_gap(const Body& b) {
  const std::vector<Vec3>& x = b.state.positions;
  const SegmentSegmentClosest q = closest_points_segment_segment(x[0], x[1], x[3], x[4]);
  return q.on_q.z() - q.on_p.z();
}

// Edge–edge proximity: f 0.5 mm over e, closer than the 1 mm gap, with no vertex near a face.
// One pass parts them to the gap, each of the four vertices by a quarter of the 0.5 mm (equal
// masses, closest points at the middles: λ = 0.5 mm / (4 · ¼ w), each moves ½ w λ).
TEST(TissueContact, EdgesCloserThanTheGapArePartedAlongTheirCommonNormal) {
  Body b = crossed_edges(0.0005);
  TissueContactSolver solver({{&b.settings, &b.state}}, {{0, 0, 1e-3, 0.3}});
  solver.begin_step();
  solver.solve(kDt, kDt);
  EXPECT_NEAR(edge_gap(b), 1e-3, 1e-9);
  EXPECT_NEAR(b.state.positions[0].z(), -0.00025, 1e-9);
  EXPECT_NEAR(b.state.positions[1].z(), -0.00025, 1e-9);
  EXPECT_NEAR(b.state.positions[3].z(), 0.00075, 1e-9);
  EXPECT_NEAR(b.state.positions[4].z(), 0.00075, 1e-9);
  EXPECT_EQ(b.state.positions[2], Vec3(0, 0, -0.02));  // the far corners take no part
  EXPECT_EQ(solver.rewound(), 0u);
}

// f, 0.5 mm over e at the step's start, ends it 2 mm under e (it passed through e, no vertex
// through a face): the edges' sides say it crossed, and it goes back over e to the gap, not on
// down (its distance, 2 mm, is beyond the gap: proximity alone would leave it crossed), and
// without the fail-safe (nothing is put back at rest).
TEST(TissueContact, AnEdgeThatPassedThroughAnotherGoesBackToTheSideItCameFrom) {
  Body b = crossed_edges(0.0005);
  TissueContactSolver solver({{&b.settings, &b.state}}, {{0, 0, 1e-3, 0.3}});
  solver.begin_step();
  b.state.positions[3].z() = b.state.positions[4].z() = -0.002;  // as an integrator would move it
  solver.solve(kDt, kDt);
  EXPECT_NEAR(edge_gap(b), 1e-3, 1e-9);
  EXPECT_GT(b.state.positions[3].z(), b.state.positions[0].z());
  EXPECT_EQ(solver.rewound(), 0u);
}

// The fail-safe: with every vertex fixed no contact can move them, so when B is carried down
// through A's face (f 5 mm under e) the step's end crosses; untangle() puts B's two moved
// vertices back where they started.
TEST(TissueContact, WhatStillCrossesAfterTheContactsIsPutBackWhereItStarted) {
  Body b = crossed_edges(0.0005, true);
  TissueContactSolver solver({{&b.settings, &b.state}}, {{0, 0, 1e-3, 0.3}});
  solver.begin_step();
  b.state.positions[3].z() = b.state.positions[4].z() = -0.005;
  b.state.velocities[3] = b.state.velocities[4] = Vec3(0, 0, -5);
  solver.solve(kDt, kDt);
  EXPECT_EQ(solver.rewound(), 2u);
  EXPECT_EQ(b.state.positions[3], Vec3(0, -0.01, 0.0005));
  EXPECT_EQ(b.state.positions[4], Vec3(0, 0.01, 0.0005));
  EXPECT_EQ(b.state.velocities[3], Vec3::Zero());
  EXPECT_EQ(b.state.positions[0], Vec3(-0.01, 0, 0));  // never moved: not counted
}

/// One cell of the rolled-mesh grid: the 8 × 5 cm knit rolled (radius 4 mm, 3 mm between turns)
/// on a fixed floor, stepped `steps` ms with self contact. Returns the first step at which it
/// crossed itself (−1: never), its x extent at the end (m) and the vertices the fail-safe put
/// back over the run.
struct RollOutcome {
  int first_crossing = -1;
  Real extent = 0;
  long rewound = 0;
};
RollOutcome play_roll(Real spacing, Real mass_scale, Real k_bending, int steps) {
  TriMesh floor_mesh = make_sheet(0.3, 0.2, 6, 4);
  FixedSelection all;
  for (std::uint32_t v = 0; v < floor_mesh.vertex_count(); ++v) all.indices.push_back(v);
  Body floor(floor_mesh, material_preset("peritoneum"), all);
  TriMesh sheet = make_prosthetic_mesh(0.08, 0.05, spacing);
  for (Vec3& p : sheet.positions) p.z() += 0.0015;
  MassSpringMaterial knit = material_preset("polypropylene-mesh");
  knit.k_bending = k_bending;
  knit.density *= mass_scale;
  if (knit.mass > 0) knit.mass *= mass_scale;
  Body mesh(sheet, knit);
  roll_sheet(mesh.state.positions, SheetRoll{1, 0.004, 0.003});
  TissueContactSolver solver({{&floor.settings, &floor.state}, {&mesh.settings, &mesh.state}},
                             {{1, 0, 1e-3, 0.3}, {1, 1, 1e-3, 0.3}});
  RollOutcome out;
  for (int n = 1; n <= steps; ++n) {
    step({&floor, &mesh}, solver, n * kDt);
    out.rewound += solver.rewound();
    if (n % 5 != 0 && n != steps) continue;  // a crossed state persists (the side memory keeps it)
    if (self_crossings(mesh.settings, mesh.state.positions) > 0) {
      out.first_crossing = n;
      break;
    }
  }
  Real lo = 1, hi = -1;
  for (const Vec3& p : mesh.state.positions) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
  out.extent = hi - lo;
  return out;
}

/// A cell of the grid: how contacts are solved, grid spacing (m), mass scale, k_bending (N/m).
struct RollCell {
  Solve solve;
  Real spacing, mass, k_bending;
};

class RolledMeshGrid : public ::testing::TestWithParam<RollCell> {};

std::vector<RollCell> roll_cells() {
  std::vector<RollCell> cells;
  for (const Solve solve : {Solve::kAfter, Solve::kCoupled})
    for (const Real spacing : {0.005, 0.0035})
      for (const Real mass : {1.0, 5.0})
        for (const Real k_bending : {0.05, 0.2, 1.5}) cells.push_back({solve, spacing, mass, k_bending});
  return cells;
}

// The rolled mesh over the grid the docs report (docs/response.md, "Tissue against tissue"):
// spacing 5 / 3.5 mm × mass ×1 / ×5 × k_bending 0.05 (the preset) / 0.2 / 1.5 N/m × implicit
// Euler after the integrators / XPBD inside the substeps, 2 s each: no cell crosses itself.
// Without the edge–edge contacts and the fail-safe 8 of the 24 cells crossed (most within 50 to
// 300 steps); with the edge–edge contacts alone 4 did.
TEST_P(RolledMeshGrid, CrossesItselfNowhere) {
  const RollCell cell = GetParam();
  g_solve = cell.solve;
  const RollOutcome r = play_roll(cell.spacing, cell.mass, cell.k_bending, 2000);
  g_solve = Solve::kAfter;
  std::printf("roll %s spacing %.1f mm mass x%.0f k_bending %.2f: first crossing at step %d, extent %.1f mm, "
              "%ld vertices put back\n",
              cell.solve == Solve::kAfter ? "implicit" : "xpbd", 1e3 * cell.spacing, cell.mass, cell.k_bending,
              r.first_crossing, 1e3 * r.extent, r.rewound);
  EXPECT_EQ(r.first_crossing, -1);
  EXPECT_GT(r.extent, 0.016) << "it does not roll up tighter than it started (16 mm across)";
}
INSTANTIATE_TEST_SUITE_P(, RolledMeshGrid, ::testing::ValuesIn(roll_cells()),
                         [](const ::testing::TestParamInfo<RollCell>& cell_info) {
                           const RollCell& c = cell_info.param;
                           return std::string(c.solve == Solve::kAfter ? "Implicit" : "Xpbd") + "Spacing" +
                                  std::to_string(static_cast<int>(std::lround(c.spacing * 1e4))) + "Mass" +
                                  std::to_string(static_cast<int>(c.mass)) + "Bending" +
                                  std::to_string(static_cast<int>(std::lround(c.k_bending * 100)));
                         });

/// A 2 × 2 cm mesh patch 1 mm above a fixed wall, tacked at its centre; `pull(t)` (N, +z) is
/// spread over the patch's vertices by their mass.
struct TackRig {
  Body wall;
  Body patch;
  TissueContactSolver solver;
  SurfacePoint on_patch, on_wall;
  static TriMesh patch_mesh() {
    TriMesh m = make_prosthetic_mesh(0.02, 0.02, 0.005);
    for (Vec3& p : m.positions) p.z() += 0.001;
    return m;
  }
  static FixedSelection all(std::size_t n) {
    FixedSelection f;
    for (std::uint32_t v = 0; v < n; ++v) f.indices.push_back(v);
    return f;
  }
  static MassSpringMaterial patch_material() {
    MassSpringMaterial m = material_preset("polypropylene-mesh");
    m.mass = 0.02;  // heavier than the knit (16 mg), so a 30 N pull stays a few mm per step at 1 ms
    return m;
  }
  TackRig()
      : wall(make_sheet(0.04, 0.04, 8, 8), material_preset("peritoneum"), all(81)),
        patch(patch_mesh(), patch_material()),
        solver({{&wall.settings, &wall.state}, {&patch.settings, &patch.state}}, {}) {}

  std::size_t tack() {
    on_patch = surface_point_at(patch, 1, Vec3(0.0012, 0.0007, 0.001));
    on_wall = surface_point_at(wall, 0, Vec3(0.0012, 0.0007, 0));
    AttachmentSpec spec;
    spec.a = on_patch;
    spec.b = on_wall;
    // Held where it lies, as the tacker fixes it (procedure/tacker.cpp): 1 mm over the wall.
    spec.offset = surface_frame(wall.settings, wall.state, on_wall).transpose() *
                  (surface_position(patch.settings, patch.state, on_patch) - surface_position(wall.settings, wall.state, on_wall));
    return solver.attach(spec);
  }
  Real gap() const {
    return (surface_position(patch.settings, patch.state, on_patch) - surface_position(wall.settings, wall.state, on_wall))
        .norm();
  }
  void run(Real seconds, Real t0, const std::function<Real(Real)>& pull) {
    const Real total_mass = patch.settings.total_mass();
    for (int n = 1; n <= static_cast<int>(seconds / kDt + 0.5); ++n) {
      const Real t = t0 + n * kDt;
      patch.loads.clear();
      for (std::uint32_t v = 0; v < patch.settings.vertex_count(); ++v)
        patch.loads.add_force(v, Vec3(0, 0, pull(t) * patch.settings.masses[v] / total_mass));
      step({&wall, &patch}, solver, t);
    }
  }
};

TEST_P(TissueContactBoth, TackHoldsBelowItsPulloutForce) {
  TackRig rig;
  ASSERT_EQ(rig.tack(), 0u);
  const Real rest_gap = rig.gap();
  Real max_gap = 0;
  const Real pullout = rig.solver.attachments()[0].spec.pullout_force;
  for (int k = 0; k < 30; ++k) {  // up to 70 % of the pull-out force in 0.1 s, held 0.2 s
    rig.run(0.01, k * 0.01, [&](Real t) { return 0.7 * pullout * std::min<Real>(1, t / 0.1); });
    max_gap = std::max(max_gap, rig.gap());
  }
  const AttachmentState& a = rig.solver.attachments()[0];
  std::printf("tack at 70 %% of pull-out: gap %.3f mm (start %.3f), force %.2f N\n", 1e3 * max_gap, 1e3 * rest_gap, a.force);
  EXPECT_TRUE(a.holding);
  EXPECT_LT(a.torn_at, 0);
  // Stretched by its compliance: 0.7 × 28.6 N × 2e-5 m/N = 0.40 mm, within 0.1 mm.
  const Real stretch = 0.7 * pullout * a.spec.compliance;
  EXPECT_NEAR(max_gap - rest_gap, stretch, 1e-4);
  EXPECT_NEAR(a.force, 0.7 * pullout, 0.1 * pullout);  // the tack carries the pull
}

TEST_P(TissueContactBoth, TackTearsWhenThePullExceedsItsPulloutForce) {
  TackRig rig;
  ASSERT_EQ(rig.tack(), 0u);
  const Real pullout = rig.solver.attachments()[0].spec.pullout_force;
  constexpr Real kRate = 100;  // N/s
  Real force_before = 0;
  for (int n = 0; n < 600 && rig.solver.attachments()[0].holding; ++n) {
    force_before = rig.solver.attachments()[0].force;
    rig.run(kDt, n * kDt, [&](Real t) { return kRate * t; });
  }
  const AttachmentState& a = rig.solver.attachments()[0];
  std::printf("tack torn at %.3f s (pull %.2f N), force at the tear %.2f N (step before %.2f N), pull-out %.1f N\n",
              a.torn_at, kRate * a.torn_at, a.force, force_before, pullout);
  ASSERT_FALSE(a.holding);
  EXPECT_GT(a.force, pullout);
  EXPECT_LE(a.force, 1.05 * pullout);          // stated tolerance: 5 %
  EXPECT_NEAR(kRate * a.torn_at, pullout, 0.1 * pullout);
  rig.run(0.1, a.torn_at, [&](Real t) { return kRate * t; });
  EXPECT_FALSE(rig.solver.attachments()[0].holding);  // never again
  EXPECT_GT(rig.gap(), 2e-3);                          // and the patch left
}

// Coupled, a tack stretched beyond its own length within a step has come out: the wall under a
// knit patch of real mass (1 mg a vertex) jumps 8 mm away in one step (as tissue an instrument
// presses away from the mesh tacked to it). Solved as a constraint it would fling the light patch
// after the wall at metres per second (its XPBD force, m·a of 1 mg, stays far under the 28.6 N
// pull-out force); torn, the patch stays where it was. A 2 mm jump it holds.
TEST(TissueContact, CoupledTackStretchedBeyondItsLengthComesOut) {
  g_solve = Solve::kCoupled;
  const auto jump = [](Real distance) {
    FixedSelection all;
    for (std::uint32_t v = 0; v < 81; ++v) all.indices.push_back(v);
    Body wall(make_sheet(0.04, 0.04, 8, 8), material_preset("peritoneum"), all, Vec3::Zero());
    TriMesh patch_mesh = make_prosthetic_mesh(0.02, 0.02, 0.005);
    for (Vec3& p : patch_mesh.positions) p.z() += 0.001;
    Body patch(patch_mesh, material_preset("polypropylene-mesh"), {}, Vec3::Zero());
    TissueContactSolver solver({{&wall.settings, &wall.state}, {&patch.settings, &patch.state}}, {});
    AttachmentSpec spec;
    spec.a = surface_point_at(patch, 1, Vec3(0, 0, 0.001));
    spec.b = surface_point_at(wall, 0, Vec3::Zero());
    spec.offset = Vec3(0, 0, 0.001);  // the wall's frame here is the world's
    EXPECT_EQ(solver.attach(spec), 0u);
    for (int n = 1; n <= 10; ++n) step({&wall, &patch}, solver, n * kDt);
    for (Vec3& p : wall.state.positions) p.z() -= distance;  // the wall jumps away
    Real fastest = 0;
    for (int n = 11; n <= 20; ++n) {
      step({&wall, &patch}, solver, n * kDt);
      for (const Vec3& v : patch.state.velocities) fastest = std::max(fastest, v.norm());
    }
    return std::make_pair(solver.attachments()[0], fastest);
  };
  const auto [torn, torn_fastest] = jump(0.008);
  const auto [held, held_fastest] = jump(0.002);
  std::printf("coupled tack, wall jumps 8 mm: holding %d, stretched out %d, torn at %.3f s, fastest patch vertex %.3g m/s; "
              "2 mm: holding %d, fastest %.3g m/s\n", torn.holding, torn.stretched_out, torn.torn_at, torn_fastest,
              held.holding, held_fastest);
  EXPECT_FALSE(torn.holding);
  EXPECT_TRUE(torn.stretched_out);
  EXPECT_NEAR(torn.torn_at, 0.011, 1e-9);  // in the step of the jump
  EXPECT_LT(torn_fastest, 0.01);            // left where it was, at rest
  EXPECT_TRUE(held.holding);
  EXPECT_FALSE(held.stretched_out);
  EXPECT_LT(held_fastest, 4.0);  // drawn after the wall: the jump's own 2 m/s, at most twice that
  g_solve = Solve::kAfter;
}

// A tack between a mesh of real mass (the preset's 1 mg a vertex) and a wall whose contact keeps
// them 1 mm apart, fired where the mesh lies 1.5 mm over the wall (the TAPP groin's lay): held at
// that offset, both stay at rest where they were. Held at zero offset instead (before the
// offset), tack and contact undid each other by a millimetre per iteration and the TAPP scene
// blew up within 10 ms of the first tack.
TEST_P(TissueContactBoth, ATackAcrossTheContactGapHoldsTheMeshWhereItLies) {
  constexpr Real kLay = 0.0015;
  FixedSelection border;
  for (std::uint32_t v = 0; v < 81; ++v)
    if (v % 9 == 0 || v % 9 == 8 || v < 9 || v >= 72) border.indices.push_back(v);
  // No gravity: the tack and the contact alone.
  Body wall(make_sheet(0.04, 0.04, 8, 8), material_preset("peritoneum"), border, Vec3::Zero());
  TriMesh patch_mesh = make_prosthetic_mesh(0.02, 0.02, 0.005);
  for (Vec3& p : patch_mesh.positions) p.z() += kLay;
  Body patch(patch_mesh, material_preset("polypropylene-mesh"), {}, Vec3::Zero());
  ASSERT_LT(patch.settings.masses[0], 2e-6);  // the knit's own mass
  TissueContactSolver solver({{&wall.settings, &wall.state}, {&patch.settings, &patch.state}},
                             {{1, 0, 1e-3, 0.5, 20, 0.002}});
  // The tack at the patch's centre vertex and the wall point under it.
  const Vec3 centre(0, 0, kLay);
  const SurfacePoint on_patch = surface_point_at(patch, 1, centre), on_wall = surface_point_at(wall, 0, Vec3::Zero());
  AttachmentSpec spec;
  spec.a = on_patch;
  spec.b = on_wall;
  spec.offset = surface_frame(wall.settings, wall.state, on_wall).transpose() * Vec3(0, 0, kLay);
  ASSERT_EQ(solver.attach(spec), 0u);
  // Adhesion draws the patch from 1.5 mm down to the contact's 1 mm round the tack, at up to
  // 0.22 m/s after the integrators and 0.06 m/s inside the substeps (measured); the blow-up
  // reached 10–100 m/s.
  Real fastest = 0, fastest_end = 0;
  for (int n = 1; n <= 500; ++n) {
    step({&wall, &patch}, solver, n * kDt);
    fastest_end = 0;
    for (const Body* b : {&wall, &patch})
      for (const Vec3& v : b->state.velocities) fastest_end = std::max(fastest_end, v.norm());
    fastest = std::max(fastest, fastest_end);
  }
  const Vec3 held = surface_position(patch.settings, patch.state, on_patch) - surface_position(wall.settings, wall.state, on_wall);
  std::printf("tack across the 1 mm contact gap: separation %.3f mm (laid %.1f), fastest vertex %.2g m/s (at the end "
              "%.2g), force %.2g N\n", 1e3 * held.norm(), 1e3 * kLay, fastest, fastest_end, solver.attachments()[0].force);
  EXPECT_TRUE(solver.attachments()[0].holding);
  EXPECT_NEAR(held.z(), kLay, 2e-4);     // where it lay (the adhesion round it draws it 0.12 mm down)
  EXPECT_LT(held.head<2>().norm(), 1e-4);
  EXPECT_LT(fastest, 0.5);
  // Quiet: where adhesion (to 1 mm) and the tack (at 1.5 mm) meet round it, the vertices shimmer
  // at 0.011 m/s after the integrators, 0.003 m/s inside the substeps (measured); without
  // adhesion they come to rest (10⁻¹⁵ m/s).
  EXPECT_LT(fastest_end, 0.05);
  EXPECT_LT(solver.attachments()[0].force, 0.01);
}

TEST(TissueContact, BadAttachmentSpecsAndAFullCapacityAreRefused) {
  TriMesh m = make_sheet(0.01, 0.01, 2, 2);
  MassSpringSettings s = MassSpringSettings::build(m, MassSpringMaterial{});
  MassSpringState x = MassSpringState::at_rest(s);
  TissueContactSolver solver({{&s, &x}}, {}, 2);
  const std::size_t refused = std::numeric_limits<std::size_t>::max();
  AttachmentSpec ok;
  ok.a = {0, 0, Vec3(1, 0, 0)};
  ok.b = {0, 7, Vec3(0.2, 0.3, 0.5)};
  AttachmentSpec bad = ok;
  bad.a.tissue = 1;
  EXPECT_EQ(solver.attach(bad), refused);
  bad = ok;
  bad.b.triangle = 8;
  EXPECT_EQ(solver.attach(bad), refused);
  bad = ok;
  bad.b.bary = Vec3(0.5, 0.5, 0.5);
  EXPECT_EQ(solver.attach(bad), refused);
  bad = ok;
  bad.b.bary = Vec3(std::nan(""), 0, 1);
  EXPECT_EQ(solver.attach(bad), refused);
  bad = ok;
  bad.offset = Vec3(0, 0, std::numeric_limits<Real>::infinity());
  EXPECT_EQ(solver.attach(bad), refused);
  EXPECT_EQ(solver.attach(ok), 0u);
  EXPECT_EQ(solver.attach(ok), 1u);
  EXPECT_EQ(solver.attach(ok), refused);  // capacity 2
  EXPECT_EQ(solver.attachments().size(), 2u);
}

TEST(TissueContact, NoPairsAndNoAttachmentsChangeNothing) {
  TriMesh m = make_sheet(0.01, 0.01, 2, 2);
  MassSpringSettings s = MassSpringSettings::build(m, MassSpringMaterial{}, {}, kGravity);
  MassSpringState x = MassSpringState::at_rest(s);
  x.velocities[3] = Vec3(0.1, 0.2, -0.3);
  x.positions[4].z() = -1;  // through the sheet: nobody asked for contact
  const MassSpringState before = x;
  TissueContactSolver solver({{&s, &x}}, {});
  solver.begin_step();
  solver.solve(kDt, kDt);
  EXPECT_EQ(x.positions, before.positions);
  EXPECT_EQ(x.velocities, before.velocities);
  EXPECT_EQ(solver.corrected(), 0u);
}

TEST(ProstheticMesh, IsACleanOpenSheetWithUvsInMetres) {
  const TriMesh m = make_prosthetic_mesh(0.15, 0.10, 0.005);
  EXPECT_EQ(m.vertex_count(), 31u * 21u);
  EXPECT_EQ(m.triangle_count(), 2u * 30u * 20u);
  EXPECT_TRUE(validate(m).is_clean_open());
  ASSERT_EQ(m.texcoords.size(), 3 * m.triangle_count());
  for (std::size_t t = 0; t < m.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.positions[m.triangles[t][k]];
      EXPECT_NEAR(m.texcoords[3 * t + k].x(), p.x() + 0.075, 1e-12);
      EXPECT_NEAR(m.texcoords[3 * t + k].y(), p.y() + 0.05, 1e-12);
    }
  EXPECT_NEAR(m.area(), 0.015, 1e-12);
  EXPECT_THROW(make_prosthetic_mesh(0.1, -1, 0.005), Error);
  EXPECT_THROW(make_prosthetic_mesh(0.1, 0.1, 0), Error);
}

TEST(ProstheticMesh, RollKeepsLengthsAlongTheAxisAndArcLengthsAcross) {
  const TriMesh m = make_prosthetic_mesh(0.1, 0.04, 0.005);
  std::vector<Vec3> x = m.positions;
  roll_sheet(x, SheetRoll{1, 0.004, 0.002});  // axis y: x becomes arc length
  const MassSpringSettings s = MassSpringSettings::build(m, MassSpringMaterial{});
  Real worst_along = 0, worst_across = 0, lowest = 1;
  for (std::size_t e = 0; e < s.structural_count; ++e) {
    const Spring& sp = s.springs[e];
    const Real l = (x[sp.i] - x[sp.j]).norm();
    const Vec3 d0 = m.positions[sp.i] - m.positions[sp.j];
    if (std::abs(d0.x()) < 1e-12) worst_along = std::max(worst_along, std::abs(l - sp.rest_length));
    else if (std::abs(d0.y()) < 1e-12) worst_across = std::max(worst_across, (sp.rest_length - l) / sp.rest_length);
  }
  for (const Vec3& p : x) lowest = std::min(lowest, p.z());
  EXPECT_LT(worst_along, 1e-12);
  // A 5 mm chord on the 4 mm inner turn: l³/24r² = 0.33 mm short (6.5 %).
  EXPECT_LT(worst_across, 0.07);
  EXPECT_GT(worst_across, 0.0);
  EXPECT_NEAR(lowest, 0, 1e-9);  // rests on the former plane
  std::vector<Vec3> tilted = m.positions;
  tilted[0].z() = 0.01;
  EXPECT_THROW(roll_sheet(tilted, SheetRoll{}), Error);
  EXPECT_THROW(roll_sheet(x = m.positions, SheetRoll{2, 0.004, 0.002}), Error);
}

}  // namespace
}  // namespace trocar
