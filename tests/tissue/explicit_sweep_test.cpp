// The explicit step as one sweep over blocks of vertices (explicit_sweep.h) against the
// pass-by-pass step and against accumulate_forces: same physics to rounding, with every term but
// the area term, fixed vertices and external forces, where the ring of slots wraps around many
// times (a banded order, small blocks) and where it cannot (the generator's order).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "trocar/core/cpu_features.h"
#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/renumber.h"
#include "trocar/tissue/explicit_sweep.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/integrator.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

using tissue_detail::ExplicitSweep;

/// Every term but area: spring damping, global damping, volume, home springs, gravity; the bottom
/// of the mesh fixed.
MassSpringSettings sweep_settings(const TriMesh& mesh, Real mass = 0.05) {
  MassSpringMaterial m;
  m.mass = mass;
  m.k_structural = 40;
  m.k_bending = 4;
  m.spring_damping = 0.01;
  m.damping = 3;
  m.k_area = 0;
  m.k_volume = 500;
  m.k_home = 5;
  const Aabb box = mesh.bounds();
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, box.min.z() + 0.2 * (box.max.z() - box.min.z())), Vec3(0, 0, 1)};
  return MassSpringSettings::build(mesh, m, fixed, Vec3(0, 0, -9.81));
}

/// A moving, deformed start: free vertices displaced by up to 3 % of the size, random speeds.
MassSpringState moving_start(const MassSpringSettings& s, Real size) {
  MassSpringState st = MassSpringState::at_rest(s);
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (std::size_t i = 0; i < st.positions.size(); ++i) {
    if (s.fixed[i]) continue;
    st.positions[i] += 0.03 * size * Vec3(u(rng), u(rng), u(rng));
    st.velocities[i] = 0.05 * Vec3(u(rng), u(rng), u(rng));
  }
  return st;
}

/// Forces on every 5th vertex, added in a shuffled order (the sweep sorts them).
TissueLoads shuffled_loads(std::size_t n) {
  std::vector<std::uint32_t> loaded;
  for (std::uint32_t i = 0; i < n; i += 5) loaded.push_back(i);
  std::shuffle(loaded.begin(), loaded.end(), std::mt19937(3));
  TissueLoads loads;
  loads.reset(n);
  for (const std::uint32_t i : loaded) loads.add_force(i, Vec3(0.01, -0.02, 0.005 * (i % 3)));
  return loads;
}

TriMesh banded(TriMesh mesh) { return renumber_vertices(mesh, locality_vertex_order(mesh)); }

/// One step of `sweep` against accumulate_forces: v1 = v + h (f + f_ext)/m, x1 = x + h v1 (or v),
/// for both explicit integrators; also the returned Σ of the coordinates.
void expect_step_matches_accumulate_forces(const MassSpringSettings& s, ExplicitSweep& sweep, const std::string& label) {
  const std::size_t n = s.vertex_count();
  const MassSpringState start = moving_start(s, 0.04);
  const TissueLoads loads = shuffled_loads(n);
  std::vector<Vec3> f(n, Vec3::Zero());
  accumulate_forces(s, start.positions, start.velocities, f);
  const Real h = 1e-4;
  Real largest_speed_change = 0;
  for (std::size_t i = 0; i < n; ++i)
    largest_speed_change = std::max(largest_speed_change, (h * s.inverse_masses[i] * (f[i] + loads.forces()[i])).norm());
  ASSERT_GT(largest_speed_change, 1e-4);
  for (const bool symplectic : {false, true}) {
    MassSpringState st = start;
    for (std::size_t i = 0; i < n; ++i)
      if (s.fixed[i]) st.velocities[i].setZero();  // as the integrator does before a step
    const Real check = sweep.step(st.positions.data(), st.velocities.data(), loads, ForceTerms{}, h, symplectic);
    Real worst_v = 0, worst_x = 0, sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 v0 = s.fixed[i] ? Vec3::Zero() : start.velocities[i];
      const Vec3 v1 = v0 + h * s.inverse_masses[i] * (f[i] + loads.forces()[i]);
      const Vec3 x1 = start.positions[i] + h * (symplectic ? v1 : v0);
      worst_v = std::max(worst_v, (st.velocities[i] - v1).norm());
      worst_x = std::max(worst_x, (st.positions[i] - x1).norm());
      sum += st.positions[i].sum() + st.velocities[i].sum();
    }
    std::cout << "[ figures  ] sweep, " << label << ", window " << sweep.window() << " of " << n
              << (symplectic ? ", semi-implicit" : ", explicit") << ": |Δv| " << worst_v
              << " m/s (speed changes up to " << largest_speed_change << "), |Δx| " << worst_x << " m\n";
    EXPECT_LT(worst_v, 1e-12 * largest_speed_change);
    EXPECT_LT(worst_x, 1e-15);
    EXPECT_NEAR(check, sum, 1e-12 * std::abs(sum));
  }
}

// In the generator's order (the window is nearly all of the mesh) and in a banded order with
// blocks of 8 (the window is a fraction of it, so the slots wrap around).
TEST(ExplicitSweep, OneStepMatchesAccumulateForces) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "the sweep needs AVX2 and FMA";
  for (const bool band : {false, true}) {
    const TriMesh sphere = make_icosphere(0.02, 3);
    const MassSpringSettings s = sweep_settings(band ? banded(sphere) : sphere);
    ASSERT_TRUE(s.closed);
    ExplicitSweep sweep(s, 8);
    if (band) {
      EXPECT_LT(sweep.window(), s.vertex_count() / 4) << "the ring must wrap around";
    }
    EXPECT_LE(sweep.window(), s.vertex_count());
    // Structural and bending springs: two (k, λ) classes, so the stars are one cache line each.
    EXPECT_TRUE(sweep.plan().stars.empty());
    EXPECT_GT(sweep.plan().compact_stars.size(), s.springs.size() / 8);
    expect_step_matches_accumulate_forces(s, sweep, band ? "banded" : "generator order");
  }
}

// Springs of more than two (k, λ) classes (edited settings) keep the 128-byte star quads, with
// each spring's own parameters.
TEST(ExplicitSweep, ThreeSpringClassesKeepFullQuads) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "the sweep needs AVX2 and FMA";
  MassSpringSettings s = sweep_settings(banded(make_icosphere(0.02, 3)));
  for (std::size_t e = 0; e < s.springs.size(); e += 3) s.springs[e].stiffness *= 1.5;
  ExplicitSweep sweep(s, 8);
  EXPECT_TRUE(sweep.plan().compact_stars.empty());
  EXPECT_GT(sweep.plan().stars.size(), s.springs.size() / 8);
  expect_step_matches_accumulate_forces(s, sweep, "three classes");
}

// The integrator with the sweep on and off, 200 semi-implicit steps on the shared liver: the two
// trajectories agree to rounding (the forces are summed in another order), and the sweep keeps
// the fixed vertices bit for bit.
TEST(ExplicitSweep, SharedLiverTrajectoryMatchesThePasses) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "the sweep needs AVX2 and FMA";
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.obj");
  TriMesh mesh = load_mesh(path.string());
  for (Vec3& p : mesh.positions) p *= 0.01;  // cm → m
  const MassSpringSettings s = sweep_settings(banded(mesh), 1.0);  // a 1 kg liver
  const std::size_t n = s.vertex_count();
  MassSpringIntegrator passes(s, IntegratorKind::kSemiImplicitEuler), swept(s, IntegratorKind::kSemiImplicitEuler);
  passes.set_explicit_sweep(false);
  swept.set_explicit_sweep(true);
  ASSERT_FALSE(passes.explicit_sweep());
  ASSERT_TRUE(swept.explicit_sweep());
  MassSpringState a = moving_start(s, 0.01), b = a;
  const MassSpringState start = a;
  const TissueLoads loads = shuffled_loads(n);
  for (int step = 0; step < 200; ++step) {
    ASSERT_TRUE(passes.step(a, loads, 1e-4).finite);
    ASSERT_TRUE(swept.step(b, loads, 1e-4).finite);
  }
  Real motion = 0, worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    motion = std::max(motion, (a.positions[i] - start.positions[i]).norm());
    worst = std::max(worst, (a.positions[i] - b.positions[i]).norm());
    if (s.fixed[i]) {
      EXPECT_EQ(std::memcmp(b.positions[i].data(), start.positions[i].data(), sizeof(Vec3)), 0) << i;
      EXPECT_EQ(b.velocities[i], Vec3::Zero());
    }
  }
  std::cout << "[ figures  ] liver, 200 steps: sweep vs passes |Δx| " << worst << " m, largest motion " << motion
            << " m\n";
  EXPECT_GT(motion, 1e-4);
  EXPECT_LT(worst, 1e-11 * motion);
}

// Turning a term off in ForceTerms turns it off in the sweep as well: with the springs off and
// no volume, gravity, damping or home term, a step is a free drift x1 = x + h v.
TEST(ExplicitSweep, TermsSwitchOff) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "the sweep needs AVX2 and FMA";
  const MassSpringSettings s = sweep_settings(banded(make_icosphere(0.02, 2)));
  ExplicitSweep sweep(s, 16);
  MassSpringState st = moving_start(s, 0.04);
  for (std::size_t i = 0; i < st.velocities.size(); ++i)
    if (s.fixed[i]) st.velocities[i].setZero();
  const MassSpringState start = st;
  ForceTerms off;
  off.springs = off.volume = off.home = off.global_damping = off.gravity = false;
  const TissueLoads none;
  sweep.step(st.positions.data(), st.velocities.data(), none, off, 1e-3, true);
  for (std::size_t i = 0; i < st.positions.size(); ++i) {
    EXPECT_EQ(st.velocities[i], start.velocities[i]) << i;
    EXPECT_NEAR((st.positions[i] - (start.positions[i] + 1e-3 * start.velocities[i])).norm(), 0, 1e-18) << i;
  }
}

// Where the sweep is the default and the area term cannot apply, the pass-by-pass arrays are only
// built when a setter turns the sweep or the AVX2 passes off; the steps then agree to rounding.
TEST(ExplicitSweep, PassByPassBuiltWhenTurnedOn) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "the sweep needs AVX2 and FMA";
  const MassSpringSettings s = sweep_settings(banded(make_icosphere(0.05, 6)));  // 40,962 vertices
  ASSERT_TRUE(tissue_detail::sweep_pays(s)) << tissue_detail::pass_by_pass_bytes(s) << " bytes";
  MassSpringIntegrator swept(s, IntegratorKind::kSemiImplicitEuler), passes(s, IntegratorKind::kSemiImplicitEuler),
      scalar(s, IntegratorKind::kSemiImplicitEuler);
  ASSERT_TRUE(swept.explicit_sweep());
  passes.set_explicit_sweep(false);
  scalar.set_simd(false);
  ASSERT_FALSE(passes.explicit_sweep());
  ASSERT_FALSE(scalar.explicit_sweep());
  const MassSpringState start = moving_start(s, 0.1);
  MassSpringState a = start, b = start, c = start;
  const TissueLoads loads = shuffled_loads(s.vertex_count());
  for (int step = 0; step < 3; ++step) {
    ASSERT_TRUE(swept.step(a, loads, 1e-4).finite);
    ASSERT_TRUE(passes.step(b, loads, 1e-4).finite);
    ASSERT_TRUE(scalar.step(c, loads, 1e-4).finite);
  }
  Real motion = 0, worst_passes = 0, worst_scalar = 0;
  for (std::size_t i = 0; i < s.vertex_count(); ++i) {
    motion = std::max(motion, (a.positions[i] - start.positions[i]).norm());
    worst_passes = std::max(worst_passes, (a.positions[i] - b.positions[i]).norm());
    worst_scalar = std::max(worst_scalar, (a.positions[i] - c.positions[i]).norm());
  }
  EXPECT_GT(motion, 1e-6);
  EXPECT_LT(worst_passes, 1e-12 * motion);
  EXPECT_LT(worst_scalar, 1e-12 * motion);
}

TEST(ExplicitSweep, BytesOfThePassesAndBadBlock) {
  // Icosphere of level 1: 42 vertices, 120 edges, 80 triangles, 120 bending springs.
  const MassSpringSettings s = sweep_settings(make_icosphere(0.02, 1));
  ASSERT_EQ(s.vertex_count(), 42u);
  ASSERT_EQ(s.springs.size(), 240u);
  EXPECT_EQ(tissue_detail::pass_by_pass_bytes(s), 42u * 224 + 240u * 32 + 80u * 6);
  EXPECT_FALSE(tissue_detail::sweep_pays(s));  // 17.6 kB: in any L2
  EXPECT_THROW(ExplicitSweep(s, 0), Error);
}

}  // namespace
}  // namespace trocar
