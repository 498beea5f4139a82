// Force terms of the mass-spring tissue: zero at rest, frame invariance, forces = −∇E,
// stiffness and damping products against finite differences, degenerate geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/settings.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

using Vecs = std::vector<Vec3>;

/// Every term with a nonzero coefficient (volume only acts on closed meshes).
MassSpringMaterial all_terms_material() {
  MassSpringMaterial m;
  m.mass = 0.2;
  m.k_structural = 300;
  m.k_bending = 30;
  m.spring_damping = 0.05;
  m.damping = 0.5;
  m.k_area = 200;
  m.k_volume = 5e4;
  m.k_home = 10;
  return m;
}

MassSpringSettings sphere_settings(int level = 1, const Vec3& gravity = Vec3::Zero()) {
  return MassSpringSettings::build(make_icosphere(0.05, level), all_terms_material(), {}, gravity);
}
MassSpringSettings sheet_settings(const Vec3& gravity = Vec3::Zero()) {
  return MassSpringSettings::build(make_sheet(0.2, 0.1, 6, 4, 0.02), all_terms_material(), {}, gravity);
}

/// Only the named term switched on.
enum class Term { springs, area, volume, home, global_damping, gravity };
ForceTerms only(Term t) {
  ForceTerms f{false, false, false, false, false, false};
  switch (t) {
    case Term::springs: f.springs = true; break;
    case Term::area: f.area = true; break;
    case Term::volume: f.volume = true; break;
    case Term::home: f.home = true; break;
    case Term::global_damping: f.global_damping = true; break;
    case Term::gravity: f.gravity = true; break;
  }
  return f;
}
const char* name(Term t) {
  constexpr const char* names[] = {"springs", "area", "volume", "home", "global_damping", "gravity"};
  return names[static_cast<int>(t)];
}

Vecs forces_of(const MassSpringSettings& s, const Vecs& x, const Vecs& v, const ForceTerms& terms) {
  Vecs f(x.size(), Vec3::Zero());
  accumulate_forces(s, x, v, f, terms);
  return f;
}
Vecs zeros(std::size_t n) { return Vecs(n, Vec3::Zero()); }

Real max_norm(const Vecs& a) {
  Real m = 0;
  for (const Vec3& p : a) m = std::max(m, p.norm());
  return m;
}
Real max_diff(const Vecs& a, const Vecs& b) {
  Real m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).norm());
  return m;
}
Real dot(const Vecs& a, const Vecs& b) {
  Real d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d += a[i].dot(b[i]);
  return d;
}
Real mean_rest_length(const MassSpringSettings& s) {
  Real l = 0;
  for (std::size_t e = 0; e < s.structural_count; ++e) l += s.springs[e].rest_length;
  return l / static_cast<Real>(s.structural_count);
}

/// Rest positions with each coordinate moved uniformly in ±amplitude.
Vecs perturbed(const Vecs& x, Real amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-amplitude, amplitude);
  Vecs y = x;
  for (Vec3& p : y) p += Vec3(u(rng), u(rng), u(rng));
  return y;
}
Vecs random_vectors(std::size_t n, unsigned seed) { return perturbed(zeros(n), 1.0, seed); }
Vecs scaled(const Vecs& x, Real factor) {
  Vecs y = x;
  for (Vec3& p : y) p *= factor;
  return y;
}
Vecs axpy(const Vecs& x, Real a, const Vecs& d) {
  Vecs y = x;
  for (std::size_t i = 0; i < y.size(); ++i) y[i] += a * d[i];
  return y;
}

/// A rigid motion: rotation about a generic axis, then a large translation.
Vecs rigidly_moved(const Vecs& x, const Mat3& r, const Vec3& t) {
  Vecs y = x;
  for (Vec3& p : y) p = r * p + t;
  return y;
}
Mat3 some_rotation() { return Eigen::AngleAxis<Real>(1.1, Vec3(1, -2, 0.5).normalized()).toRotationMatrix(); }

TEST(TissueForces, AtRestEveryTermIsZero) {
  for (const MassSpringSettings& s : {sphere_settings(2), sheet_settings()}) {
    const Real scale = s.springs.front().stiffness * mean_rest_length(s);  // k·l (N)
    const Vecs v = zeros(s.vertex_count());
    for (Term t : {Term::springs, Term::area, Term::volume, Term::home, Term::global_damping, Term::gravity}) {
      const Vecs f = forces_of(s, s.rest_positions, v, only(t));
      EXPECT_LE(max_norm(f), 1e-12 * scale) << name(t);
    }
    EXPECT_LE(max_norm(forces_of(s, s.rest_positions, v, ForceTerms{})), 1e-12 * scale);
    EXPECT_NEAR(potential_energy(s, s.rest_positions, ForceTerms{}), 0, 1e-20);
  }
}

TEST(TissueForces, AccumulatesIntoTheCallersArray) {
  const MassSpringSettings s = sphere_settings(1, Vec3(0, 0, -9.81));
  Vecs f(s.vertex_count(), Vec3(1, 2, 3));
  accumulate_forces(s, s.rest_positions, zeros(s.vertex_count()), f, only(Term::gravity));
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_LE((f[i] - Vec3(1, 2, 3 - 9.81 * s.masses[i])).norm(), 1e-12);
}

TEST(TissueForces, RigidMotionGivesNoElasticForce) {
  const Vec3 far(3.0, -7.0, 12.0);  // metres: far from the origin, to test the volume's origin
  for (const MassSpringSettings& s : {sphere_settings(2), sheet_settings()}) {
    const Real scale = s.springs.front().stiffness * mean_rest_length(s);
    const Vecs x = rigidly_moved(s.rest_positions, some_rotation(), far);
    const Vecs v = zeros(s.vertex_count());
    for (Term t : {Term::springs, Term::area, Term::volume})
      EXPECT_LE(max_norm(forces_of(s, x, v, only(t))), 1e-10 * scale) << name(t);
  }
}

TEST(TissueForces, DeformedForcesRotateWithTheMesh) {
  // Frame invariance away from rest: f(R x + t) = R f(x) for each elastic term.
  const MassSpringSettings s = sphere_settings(2);
  const Vecs x = perturbed(s.rest_positions, 0.004, 1);
  const Mat3 r = some_rotation();
  const Vecs y = rigidly_moved(x, r, Vec3(-2.0, 5.0, 1.0));
  const Vecs v = zeros(s.vertex_count());
  for (Term t : {Term::springs, Term::area, Term::volume}) {
    const Vecs fx = forces_of(s, x, v, only(t));
    const Vecs fy = forces_of(s, y, v, only(t));
    ASSERT_GT(max_norm(fx), 0) << name(t);
    EXPECT_LE(max_diff(rigidly_moved(fx, r, Vec3::Zero()), fy), 1e-9 * max_norm(fx)) << name(t);
  }
}

/// Checks f = −∇E for one term by central differences on every coordinate.
void expect_force_is_minus_gradient(const MassSpringSettings& s, const Vecs& x, Term t) {
  const ForceTerms terms = only(t);
  const Vecs f = forces_of(s, x, zeros(x.size()), terms);
  const Real h = 1e-7;  // m (the meshes are ~0.1 m across)
  Real worst = 0;
  Vecs y = x;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      y[i][k] = x[i][k] + h;
      const Real ep = potential_energy(s, y, terms);
      y[i][k] = x[i][k] - h;
      const Real em = potential_energy(s, y, terms);
      y[i][k] = x[i][k];
      worst = std::max(worst, std::abs(-(ep - em) / (2 * h) - f[i][k]));
    }
  ASSERT_GT(max_norm(f), 0) << name(t);
  EXPECT_LE(worst, 1e-6 * max_norm(f)) << name(t) << ": worst " << worst << " of " << max_norm(f);
}

TEST(TissueForces, ForcesAreMinusGradientOfEnergyOnASphere) {
  const MassSpringSettings s = sphere_settings(1, Vec3(0.5, -1.0, -9.81));
  const Vecs x = perturbed(s.rest_positions, 0.005, 2);  // ~15 % of an edge
  for (Term t : {Term::springs, Term::area, Term::volume, Term::home, Term::gravity})
    expect_force_is_minus_gradient(s, x, t);
}

TEST(TissueForces, ForcesAreMinusGradientOfEnergyOnASheet) {
  const MassSpringSettings s = sheet_settings(Vec3(0, 0, -9.81));
  ASSERT_FALSE(s.closed);
  const Vecs x = perturbed(s.rest_positions, 0.004, 3);
  for (Term t : {Term::springs, Term::area, Term::home, Term::gravity}) expect_force_is_minus_gradient(s, x, t);
  // The volume term does not act on an open sheet.
  EXPECT_EQ(max_norm(forces_of(s, x, zeros(x.size()), only(Term::volume))), 0);
  EXPECT_EQ(potential_energy(s, x, only(Term::volume)), 0);
}

/// (∂f/∂x)·dx by central differences of the forces (v = 0).
Vecs fd_stiffness_product(const MassSpringSettings& s, const Vecs& x, const Vecs& dx, const ForceTerms& terms,
                          Real h) {
  const Vecs v = zeros(x.size());
  const Vecs fp = forces_of(s, axpy(x, h, dx), v, terms);
  const Vecs fm = forces_of(s, axpy(x, -h, dx), v, terms);
  Vecs d(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = (fp[i] - fm[i]) / (2 * h);
  return d;
}
Vecs stiffness_product(const MassSpringSettings& s, const Vecs& x, const Vecs& dx, const ForceTerms& terms) {
  Vecs out = zeros(x.size());
  add_stiffness_product(s, x, dx, out, terms);
  return out;
}

TEST(TissueForces, SpringStiffnessProductMatchesFiniteDifferencesWhenStretched) {
  // Scaled by 1.3 and perturbed by < 5 % of an edge: every spring is stretched, so the PSD
  // clamp is inactive and the product is the exact Jacobian.
  for (const MassSpringSettings& s : {sphere_settings(1), sheet_settings()}) {
    const Vecs x = perturbed(scaled(s.rest_positions, 1.3), 0.001, 4);
    for (const Spring& p : s.springs) ASSERT_GT((x[p.j] - x[p.i]).norm(), p.rest_length);
    const Vecs dx = random_vectors(x.size(), 5);
    const Vecs k = stiffness_product(s, x, dx, only(Term::springs));
    const Vecs fd = fd_stiffness_product(s, x, dx, only(Term::springs), 1e-6);
    EXPECT_LE(max_diff(k, fd), 1e-6 * max_norm(k));
  }
}

TEST(TissueForces, ConstraintStiffnessProductsAreExactAtRest) {
  // Gauss–Newton for area and volume drops κ (A − A0) ∇²A, which vanishes at rest.
  for (const MassSpringSettings& s : {sphere_settings(1), sheet_settings()}) {
    const Vecs dx = random_vectors(s.vertex_count(), 6);
    for (Term t : {Term::springs, Term::area, Term::volume, Term::home}) {
      if (t == Term::volume && !s.closed) continue;
      const Vecs k = stiffness_product(s, s.rest_positions, dx, only(t));
      const Vecs fd = fd_stiffness_product(s, s.rest_positions, dx, only(t), 1e-6);
      ASSERT_GT(max_norm(k), 0) << name(t);
      EXPECT_LE(max_diff(k, fd), 1e-6 * max_norm(k)) << name(t);
    }
  }
}

TEST(TissueForces, ConstraintStiffnessProductsApproximateNearRest) {
  // Away from rest the dropped term is O(A − A0): a 2 % perturbation stays within ~10 %.
  const MassSpringSettings s = sphere_settings(1);
  const Vecs x = perturbed(s.rest_positions, 0.0003, 7);
  const Vecs dx = random_vectors(x.size(), 8);
  for (Term t : {Term::area, Term::volume}) {
    const Vecs k = stiffness_product(s, x, dx, only(t));
    const Vecs fd = fd_stiffness_product(s, x, dx, only(t), 1e-6);
    EXPECT_LE(max_diff(k, fd), 0.1 * max_norm(k)) << name(t);
  }
}

TEST(TissueForces, StiffnessProductIsNegativeSemidefinite) {
  // Compressed (clamp active), stretched and randomly deformed states, all terms: dxᵀ K dx ≤ 0.
  for (const MassSpringSettings& s : {sphere_settings(2), sheet_settings()}) {
    for (Real factor : {0.7, 1.0, 1.3}) {
      const Vecs x = perturbed(scaled(s.rest_positions, factor), 0.003, 9);
      for (unsigned seed = 10; seed < 30; ++seed) {
        const Vecs dx = random_vectors(x.size(), seed);
        const Real q = dot(dx, stiffness_product(s, x, dx, ForceTerms{}));
        EXPECT_LE(q, 1e-12 * std::abs(q)) << factor << " " << seed;
        EXPECT_LT(q, 0);
      }
    }
  }
}

TEST(TissueForces, CompressedSpringTransverseStiffnessIsClamped) {
  // One spring compressed to half its length: the exact Jacobian has a positive (buckling)
  // transverse part k(1 − l/|d|) = −k along a sideways dx; the product clamps it to 0.
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0, 0.01, 0)};
  m.triangles = {Triangle{0, 1, 2}};
  MassSpringMaterial mat;
  mat.mass = 0.01;
  mat.k_structural = 100;
  const MassSpringSettings s = MassSpringSettings::build(m, mat);
  Vecs x = s.rest_positions;
  x[1] = Vec3(0.005, 0, 0);  // spring 0–1 at half length; the others compressed too
  Vecs dx = zeros(3);
  dx[1] = Vec3(0, 0, 1);  // out of plane: transverse to every spring that touches vertex 1
  const ForceTerms springs = only(Term::springs);
  const Vecs fd = fd_stiffness_product(s, x, dx, springs, 1e-7);
  const Vecs k = stiffness_product(s, x, dx, springs);
  EXPECT_GT(dot(dx, fd), 0);          // exact Hessian: indefinite (the spring buckles)
  EXPECT_NEAR(dot(dx, k), 0, 1e-9);   // projected: no transverse stiffness
}

TEST(TissueForces, DampingProductMatchesFiniteDifferencesInVelocity) {
  for (const MassSpringSettings& s : {sphere_settings(1), sheet_settings()}) {
    const Vecs x = perturbed(s.rest_positions, 0.004, 11);
    const Vecs v = random_vectors(x.size(), 12);
    const Vecs dv = random_vectors(x.size(), 13);
    for (const ForceTerms& terms : {only(Term::springs), only(Term::global_damping), ForceTerms{}}) {
      Vecs out = zeros(x.size());
      add_damping_product(s, x, dv, out, terms);
      const Real h = 1e-3;  // forces are linear in v: any h is exact up to rounding
      const Vecs fp = forces_of(s, x, axpy(v, h, dv), terms);
      const Vecs fm = forces_of(s, x, axpy(v, -h, dv), terms);
      Vecs fd(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) fd[i] = (fp[i] - fm[i]) / (2 * h);
      ASSERT_GT(max_norm(out), 0);
      EXPECT_LE(max_diff(out, fd), 1e-8 * max_norm(out));
      EXPECT_LT(dot(dv, out), 0);  // damping only removes energy
    }
  }
}

TEST(TissueForces, SpringDampingDoesNotDampRigidMotion) {
  const MassSpringSettings s = sphere_settings(2);
  const Vecs x = rigidly_moved(s.rest_positions, some_rotation(), Vec3(0.3, 0.1, -0.2));
  const Vec3 omega(2.0, -3.0, 5.0);  // rad/s
  const Vec3 drift(0.1, 0.2, -0.3);  // m/s
  Vecs v(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) v[i] = omega.cross(x[i]) + drift;
  Real scale = 0;
  for (const Spring& p : s.springs) scale = std::max(scale, p.damping * (v[p.j] - v[p.i]).norm());
  // The damping part alone (the elastic part at a rigidly moved rest shape is rounding-level).
  const Vecs damping_part = [&] {
    Vecs f = forces_of(s, x, v, only(Term::springs));
    const Vecs elastic = forces_of(s, x, zeros(x.size()), only(Term::springs));
    for (std::size_t i = 0; i < f.size(); ++i) f[i] -= elastic[i];
    return f;
  }();
  EXPECT_LE(max_norm(damping_part), 1e-12 * scale);
  // Whereas global damping −γ m v acts on any motion.
  EXPECT_GT(max_norm(forces_of(s, x, v, only(Term::global_damping))), 0);
  // And relative velocity along a spring is damped: stretch rate on one spring.
  Vecs w = zeros(x.size());
  w[s.springs[0].j] = x[s.springs[0].j] - x[s.springs[0].i];
  EXPECT_GT(max_norm(forces_of(s, x, w, only(Term::springs))), 0);
}

bool all_finite(const Vecs& a) {
  for (const Vec3& p : a)
    if (!p.allFinite()) return false;
  return true;
}

TEST(TissueForces, DegenerateSpringsAndTrianglesStayFinite) {
  const MassSpringSettings s = sphere_settings(1, Vec3(0, 0, -9.81));
  const Spring edge = s.springs.front();
  const Vecs v = random_vectors(s.vertex_count(), 14);
  const Vecs d = random_vectors(s.vertex_count(), 15);
  // (1) one edge collapsed: a zero-length spring and two zero-area triangles;
  // (2) one triangle's corners collinear; (3) the whole mesh collapsed to a point.
  Vecs collapsed = s.rest_positions;
  collapsed[edge.j] = collapsed[edge.i];
  Vecs collinear = s.rest_positions;
  const Triangle& t0 = s.triangles.front();
  collinear[t0[2]] = 0.5 * (collinear[t0[0]] + collinear[t0[1]]);
  const Vecs point(s.vertex_count(), Vec3(0.01, 0.02, 0.03));
  for (const Vecs& x : {collapsed, collinear, point}) {
    const Vecs f = forces_of(s, x, v, ForceTerms{});
    EXPECT_TRUE(all_finite(f));
    Vecs k = zeros(x.size());
    add_stiffness_product(s, x, d, k);
    EXPECT_TRUE(all_finite(k));
    Vecs c = zeros(x.size());
    add_damping_product(s, x, d, c);
    EXPECT_TRUE(all_finite(c));
    EXPECT_TRUE(std::isfinite(potential_energy(s, x)));
    EXPECT_LE(dot(d, k), 0);
  }
  // The zero-length spring itself contributes no force and no damping along an undefined u.
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0, 0.01, 0)};
  m.triangles = {Triangle{0, 1, 2}};
  MassSpringMaterial mat;
  mat.mass = 0.01;
  mat.k_area = 10;
  const MassSpringSettings tri = MassSpringSettings::build(m, mat);
  const Vecs x(3, Vec3(0.5, 0.5, 0.5));
  const ForceTerms springs_and_area{true, true, false, false, false, false};
  const Vecs f = forces_of(tri, x, random_vectors(3, 16), springs_and_area);
  EXPECT_TRUE(all_finite(f));
  EXPECT_EQ(max_norm(f), 0);
  // ½ κ A0² with κ = k_area/Ā0 and Ā0 = A0.
  EXPECT_NEAR(potential_energy(tri, x, only(Term::area)), 0.5 * 10 * tri.rest_areas[0], 1e-15);
}

TEST(TissueForces, KineticAndGravityEnergies) {
  const Vec3 g(0, 0, -9.81);
  const MassSpringSettings s = sphere_settings(1, g);
  const Vec3 u(0.3, -0.4, 1.2);
  const Vecs v(s.vertex_count(), u);
  EXPECT_NEAR(kinetic_energy(s, v), 0.5 * s.total_mass() * u.squaredNorm(), 1e-14);
  // Lifting the whole body by h costs M g h.
  Vecs x = s.rest_positions;
  for (Vec3& p : x) p.z() += 0.5;
  EXPECT_NEAR(potential_energy(s, x, only(Term::gravity)) - potential_energy(s, s.rest_positions, only(Term::gravity)),
              s.total_mass() * 9.81 * 0.5, 1e-12);
  // Home springs: ½ k |x − x0|² per vertex.
  EXPECT_NEAR(potential_energy(s, x, only(Term::home)), 0.5 * 10 * 0.25 * static_cast<Real>(x.size()), 1e-12);
}

TEST(TissueForces, VolumeTermIsAPressure) {
  // A sphere inflated by a factor 1 + ε: V = (1 + ε)³ V0, so every vertex is pulled inwards,
  // along its (radial) normal.
  const MassSpringSettings s = sphere_settings(2);
  const Vecs x = scaled(s.rest_positions, 1.05);
  const Vecs f = forces_of(s, x, zeros(x.size()), only(Term::volume));
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_LT(f[i].dot(x[i]), 0);
    EXPECT_GT(-f[i].normalized().dot(x[i].normalized()), 0.99);
  }
}

TEST(TissueForces, SharedLiverAtRestAndStiffnessSign) {
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.obj");
  TriMesh mesh = load_mesh(path);
  for (Vec3& p : mesh.positions) p *= 0.01;  // cm → m
  const MassSpringSettings s = MassSpringSettings::build(mesh, all_terms_material());
  const Real scale = s.springs.front().stiffness * mean_rest_length(s);
  const Vecs v = zeros(s.vertex_count());
  EXPECT_LE(max_norm(forces_of(s, s.rest_positions, v, ForceTerms{})), 1e-12 * scale);
  const Vecs x = rigidly_moved(s.rest_positions, some_rotation(), Vec3(1, 2, 3));
  EXPECT_LE(max_norm(forces_of(s, x, v, ForceTerms{false, true, true, false, false, false})), 1e-10 * scale);
  EXPECT_LE(max_norm(forces_of(s, x, v, only(Term::springs))), 1e-10 * scale);
  const Vecs y = perturbed(s.rest_positions, 0.002, 17);
  for (unsigned seed = 18; seed < 22; ++seed) {
    const Vecs dx = random_vectors(y.size(), seed);
    EXPECT_LT(dot(dx, stiffness_product(s, y, dx, ForceTerms{})), 0);
  }
}

}  // namespace
}  // namespace trocar
