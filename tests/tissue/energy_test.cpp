// ElasticEnergyMeter against the scalar reference potential_energy (gravity off): the same
// value to rounding, with every term on, on both the AVX2 and the portable passes, for a closed
// sphere, an open sheet and the shared liver.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/tissue/energy.h"
#include "trocar/tissue/forces.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

MassSpringMaterial every_term() {
  MassSpringMaterial m;
  m.mass = 0.2;
  m.k_structural = 300;
  m.k_bending = 30;
  m.k_area = 50;
  m.k_volume = 2e4;
  m.k_home = 20;
  return m;
}

/// Rest positions moved by up to ±amplitude per coordinate (deterministic).
std::vector<Vec3> perturbed(const std::vector<Vec3>& x, Real amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-amplitude, amplitude);
  std::vector<Vec3> out = x;
  for (Vec3& p : out) p += Vec3(u(rng), u(rng), u(rng));
  return out;
}

void expect_matches_reference(const MassSpringSettings& s, Real amplitude) {
  ForceTerms elastic;
  elastic.gravity = false;
  ElasticEnergyMeter meter(s);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const std::vector<Vec3> x = perturbed(s.rest_positions, amplitude, seed);
    const Real reference = potential_energy(s, x, elastic);
    ASSERT_GT(reference, 0);
    for (const bool simd : {true, false}) {
      meter.set_simd(simd);
      EXPECT_NEAR(meter.elastic(x), reference, 1e-12 * reference) << "seed " << seed << " simd " << simd;
    }
  }
  // At rest every term is zero (springs at rest length, A = A0, V = V0, x = x0).
  meter.set_simd(true);
  EXPECT_NEAR(meter.elastic(s.rest_positions), 0, 1e-15);
}

TEST(ElasticEnergyMeter, MatchesTheReferenceOnAClosedSphere) {
  const MassSpringSettings s = MassSpringSettings::build(make_icosphere(0.05, 3), every_term());
  ASSERT_TRUE(s.closed);
  expect_matches_reference(s, 0.003);
}

TEST(ElasticEnergyMeter, MatchesTheReferenceOnAnOpenSheet) {
  const MassSpringSettings s = MassSpringSettings::build(make_sheet(0.2, 0.1, 13, 7, 0.02), every_term());
  ASSERT_FALSE(s.closed);
  expect_matches_reference(s, 0.003);
}

TEST(ElasticEnergyMeter, MatchesTheReferenceOnTheSharedLiver) {
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.obj");
  TriMesh mesh = load_mesh(path);
  for (Vec3& p : mesh.positions) p *= 0.01;  // cm → m
  expect_matches_reference(MassSpringSettings::build(mesh, every_term()), 0.001);
}

}  // namespace
}  // namespace trocar

namespace trocar {
namespace {

// Coagulation changes springs in place: the meter then measures what a meter built on the changed
// settings measures.
TEST(ElasticEnergyMeterSprings, InPlaceChangeMeasuresAsAFreshMeter) {
  const TriMesh sheet = make_sheet(0.04, 0.04, 8, 8);
  MassSpringSettings s = MassSpringSettings::build(sheet, material_preset("peritoneum"));
  ElasticEnergyMeter in_place(s);
  std::vector<Vec3> x = s.rest_positions;
  for (Vec3& p : x) p *= 1.05;  // stretched: every spring stores energy
  const Real before = in_place.elastic(x);
  std::vector<std::uint32_t> changed;
  for (std::uint32_t k = 0; k < s.springs.size(); k += 5) {
    s.springs[k].stiffness *= 3;
    s.springs[k].damping *= 2;
    changed.push_back(k);
  }
  in_place.springs_changed(changed);
  ElasticEnergyMeter fresh(s);
  const Real after = in_place.elastic(x);
  EXPECT_NEAR(after, fresh.elastic(x), 1e-12 * after);
  EXPECT_GT(after, 1.2 * before);  // a fifth of the springs 3× as stiff: about 1.4×
}

}  // namespace
}  // namespace trocar
