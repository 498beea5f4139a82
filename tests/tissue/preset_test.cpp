// Material presets: every shared organ, with its preset, its bottom 12 % fixed and gravity, holds
// its shape at dt = 1 ms with the integrator the preset is meant for (docs/tissue.md, "Presets").
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/repair.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/material.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

constexpr Real kDt = 1e-3;                  ///< s
constexpr Real kSupportFraction = 0.12;     ///< bottom fraction of the height (z) that is fixed
constexpr Real kMaxSag = 5e-3;              ///< m: largest allowed displacement from rest
constexpr Real kMaxSettledSpeed = 5e-3;     ///< m/s: largest vertex speed at the end
const Vec3 kGravity(0, 0, -9.81);

/// What a run did.
struct Outcome {
  bool finite = true;
  Real max_displacement = 0;  ///< m, over all vertices at the end
  Real max_speed = 0;         ///< m/s, over all vertices at the end
  int fixed = 0;              ///< fixed vertices
  double seconds = 0;         ///< wall time of the run
};

/// Fixes every vertex in the bottom kSupportFraction of the mesh's height.
FixedSelection bottom_support(const TriMesh& mesh) {
  const Aabb box = mesh.bounds();
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, box.min.z() + kSupportFraction * (box.max.z() - box.min.z())), Vec3::UnitZ()};
  return fixed;
}

/// Runs `steps` steps of `kind` from rest under gravity and measures the end state.
Outcome settle(const TriMesh& mesh, const MassSpringMaterial& material, const FixedSelection& fixed,
               IntegratorKind kind, int steps) {
  const auto t0 = std::chrono::steady_clock::now();
  const MassSpringSettings settings = MassSpringSettings::build(mesh, material, fixed, kGravity);
  MassSpringIntegrator integrator(settings, kind);
  MassSpringState state = MassSpringState::at_rest(settings);
  TissueLoads loads;
  loads.reset(settings.vertex_count(), 0);
  Outcome out;
  for (int n = 0; n < steps && out.finite; ++n) out.finite = integrator.step(state, loads, kDt).finite;
  for (std::size_t i = 0; i < settings.vertex_count(); ++i) {
    out.finite = out.finite && state.positions[i].allFinite() && state.velocities[i].allFinite();
    out.max_displacement = std::max(out.max_displacement, (state.positions[i] - settings.rest_positions[i]).norm());
    out.max_speed = std::max(out.max_speed, state.velocities[i].norm());
    out.fixed += settings.fixed[i];
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

/// A shared organ mesh in metres; empty when the file is absent (the test then skips).
std::optional<TriMesh> shared_organ(const char* file, Real scale) {
  const std::optional<std::filesystem::path> path = test::shared_mesh_path(file);
  if (!path) return std::nullopt;
  TriMesh mesh = load_mesh(*path);
  for (Vec3& p : mesh.positions) p *= scale;
  return mesh;
}

void report(const char* name, const TriMesh& mesh, const Outcome& out, int steps) {
  std::printf("[ preset ] %-15s V=%6zu fixed=%5d steps=%4d  sag %.3f mm  max speed %.3g mm/s  (%.2f s)\n", name,
              mesh.vertex_count(), out.fixed, steps, out.max_displacement * 1e3, out.max_speed * 1e3, out.seconds);
}

/// One organ: preset `name`, integrator implicit-euler (what every organ preset is meant for).
void check_organ(const char* name, const char* file, Real scale, int steps) {
  const std::optional<TriMesh> mesh = shared_organ(file, scale);
  if (!mesh) GTEST_SKIP() << test::shared_absent(file);
  const Outcome out = settle(*mesh, material_preset(name), bottom_support(*mesh), IntegratorKind::kImplicitEuler, steps);
  report(name, *mesh, out, steps);
  EXPECT_GT(out.fixed, 0);
  ASSERT_TRUE(out.finite) << name;
  EXPECT_LE(out.max_displacement, kMaxSag) << name << " sags " << out.max_displacement * 1e3 << " mm";
  EXPECT_LE(out.max_speed, kMaxSettledSpeed) << name << " still moves at " << out.max_speed * 1e3 << " mm/s";
}

// 2194 V, 1.5 kg, 1.5 s simulated.
TEST(Preset, LiverHoldsItsShapeUnderGravity) { check_organ("liver", "liver_sofa_smooth.obj", 0.01, 1500); }
// 7352 V, 70 g, 1 s.
TEST(Preset, GallbladderHoldsItsShapeUnderGravity) { check_organ("gallbladder", "gallbladder_lapgym.stl", 0.001, 1000); }
// 4694 V, 150 g, 1 s. The file is closed and manifold as shipped (SOURCES.md): no repair.
TEST(Preset, StomachHoldsItsShapeUnderGravity) {
  check_organ("stomach", "stomach_bodyparts3d_FMA7148.obj", 0.001, 1000);
}
// 15969 V, 1.6 kg; 0.6 s (the largest mesh and the largest cost of this test).
TEST(Preset, AbdominalWallHoldsItsShapeUnderGravity) {
  check_organ("abdominal_wall", "abdominal_wall_openhelp.stl", 0.001, 600);
}

// The peritoneum preset on a 20 × 20 cm sheet (41 × 41 vertices) clamped along its border.
TEST(Preset, PeritoneumSheetClampedAtItsBorderHoldsUnderGravity) {
  const TriMesh sheet = make_sheet(0.2, 0.2, 40, 40);
  FixedSelection fixed;
  for (std::size_t i = 0; i < sheet.vertex_count(); ++i) {
    const Vec3& p = sheet.positions[i];
    if (std::abs(p.x()) > 0.0999 || std::abs(p.y()) > 0.0999) fixed.indices.push_back(static_cast<std::uint32_t>(i));
  }
  const Outcome out = settle(sheet, material_preset("peritoneum"), fixed, IntegratorKind::kImplicitEuler, 1000);
  report("peritoneum", sheet, out, 1000);
  ASSERT_TRUE(out.finite);
  EXPECT_LE(out.max_displacement, kMaxSag);
  EXPECT_LE(out.max_speed, kMaxSettledSpeed);
}

// The generic preset with the integrator it is meant for (semi-implicit) on a coarse 5 cm
// sphere (642 V, 0.55 kg from density), 3 s (semi-implicit Euler has no numerical damping, so
// only γ settles it): stable and settled; it is soft, so its sag bound is 2 cm.
TEST(Preset, SoftIsStableSemiImplicitOnACoarseSphere) {
  const TriMesh sphere = make_icosphere(0.05, 3);
  const Outcome out = settle(sphere, material_preset("soft"), bottom_support(sphere), IntegratorKind::kSemiImplicitEuler, 3000);
  report("soft", sphere, out, 3000);
  ASSERT_TRUE(out.finite);
  EXPECT_LE(out.max_displacement, 0.02);
  EXPECT_LE(out.max_speed, kMaxSettledSpeed);
}

TEST(Preset, NamesAreTheDocumentedOnesAndAllBuild) {
  const std::vector<std::string> names = material_preset_names();
  EXPECT_EQ(names, (std::vector<std::string>{"liver", "gallbladder", "abdominal_wall", "stomach", "peritoneum", "soft",
                                               "polypropylene-mesh"}));
  const TriMesh sphere = make_icosphere(0.05, 2);
  for (const std::string& name : names) {
    const MassSpringMaterial m = material_preset(name);
    EXPECT_NO_THROW(MassSpringSettings::build(sphere, m)) << name;
    EXPECT_TRUE(m.mass > 0 || m.density > 0) << name;
  }
  EXPECT_DOUBLE_EQ(material_preset("liver").mass, 1.5);
}

TEST(Preset, UnknownNameThrowsListingTheKnownOnes) {
  try {
    material_preset("nope");
    FAIL() << "no exception";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'nope'"), std::string::npos) << what;
    for (const std::string& name : material_preset_names()) EXPECT_NE(what.find(name), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace trocar
