// Material presets: one per shared organ plus a generic default. docs/tissue.md explains how the
// values were chosen and tests/tissue/preset_test.cpp checks that each organ, on its shared mesh
// in metres with its bottom 12 % fixed, holds its shape under gravity at dt = 1 ms.
#include "trocar/tissue/material.h"

#include <array>
#include <string_view>

#include "trocar/core/error.h"

namespace trocar {
namespace {

/// A preset and the integrator it is meant for (MassSpringMaterial has no field for that; the
/// name is the scene file's "integrator" value).
struct Preset {
  const char* name;
  const char* integrator;
  MassSpringMaterial material;
};

// How to read the numbers (per spring / per constraint, SI):
//  * Support. A vertex of mass m held by its home spring alone sags m·g/k_home; the mass is lumped
//    by area, so the heaviest vertex is a few times the mean. Every organ preset sets k_home so
//    that the heaviest vertex's home-spring sag is below 0.5 mm; the springs and the volume term
//    share the load with the fixed region, so the organ as a whole sags less.
//  * Stability. Explicit and semi-implicit Euler need h²·Σk/m ≲ 4 at the lightest vertex
//    (Σk: the stiffnesses of its springs plus k_home). With h = 1 ms and organ vertex masses of
//    3 mg (gallbladder) to 0.7 g (liver), that allows a few N/m to a few hundred N/m: far too soft
//    to carry the organ, so every organ preset is meant for implicit-euler.
//  * Damping. γ (1/s) damps every vertex's absolute velocity, λ (N·s/m) damps stretching only;
//    λ is set near 0.2·√(k·m̄) (m̄: mean vertex mass), well under critical.
constexpr std::array<Preset, 6> kPresets{{
    // Liver, 1.5 kg (adult liver 1.2–1.8 kg). Shared mesh: liver_sofa_smooth.obj × 0.01,
    // 2194 V, mean vertex 0.68 g. Closed: the volume term is a bulk modulus (Pa).
    {"liver", "implicit-euler",
     {.mass = 1.5, .density = 1060, .sheet_thickness = 0.002, .k_structural = 400, .k_bending = 40,
      .damping = 2, .spring_damping = 0.1, .k_area = 100, .k_volume = 2e4, .k_home = 50}},
    // Gallbladder with bile, 70 g (typically 50–100 g). Shared mesh: gallbladder_lapgym.stl ×
    // 0.001, 7352 V, mean vertex 10 mg: explicit limit about 3 N/m per spring.
    {"gallbladder", "implicit-euler",
     {.mass = 0.07, .density = 1060, .sheet_thickness = 0.002, .k_structural = 50, .k_bending = 5,
      .damping = 2, .spring_damping = 0.005, .k_area = 10, .k_volume = 5e3, .k_home = 2}},
    // Anterior abdominal wall (skin, fat, muscle), 1.2 kg. Shared mesh:
    // abdominal_wall_openhelp.stl × 0.001 (a closed thick shell), 15969 V, mean vertex 75 mg.
    {"abdominal_wall", "implicit-euler",
     {.mass = 1.2, .density = 1060, .sheet_thickness = 0.01, .k_structural = 300, .k_bending = 30,
      .damping = 2, .spring_damping = 0.02, .k_area = 50, .k_volume = 1e4, .k_home = 20}},
    // Empty stomach, 150 g. Shared mesh: stomach_bodyparts3d_FMA7148.obj × 0.001, 4694 V,
    // mean vertex 32 mg. Hollow and gas/fluid filled: the volume term stands for its content.
    {"stomach", "implicit-euler",
     {.mass = 0.15, .density = 1060, .sheet_thickness = 0.003, .k_structural = 100, .k_bending = 10,
      .damping = 2, .spring_damping = 0.01, .k_area = 20, .k_volume = 5e3, .k_home = 5}},
    // Peritoneum: a thin open sheet (≈ 0.5 mm with its fluid film); mass from density × area ×
    // thickness. Flexible (weak bending), held by its edges and home springs.
    {"peritoneum", "implicit-euler",
     {.mass = 0, .density = 1060, .sheet_thickness = 5e-4, .k_structural = 50, .k_bending = 1,
      .damping = 2, .spring_damping = 0.005, .k_area = 20, .k_volume = 0, .k_home = 2}},
    // Generic soft tissue: mass from density × volume (closed) or × area × 2 mm (open); soft
    // enough for semi-implicit-euler on coarse meshes (vertex mass ≳ 50 mg: 4·m/h² = 200 N/m
    // against Σk ≈ 6·20 + 6·2 + 1); use implicit-euler on fine meshes.
    {"soft", "semi-implicit-euler",
     {.mass = 0, .density = 1060, .sheet_thickness = 0.002, .k_structural = 20, .k_bending = 2,
      .damping = 1, .spring_damping = 0.01, .k_area = 5, .k_volume = 1e3, .k_home = 1}},
}};

}  // namespace

MassSpringMaterial material_preset(const std::string& name) {
  for (const Preset& p : kPresets)
    if (name == p.name) return p.material;
  std::string known;
  for (const Preset& p : kPresets) known += (known.empty() ? "" : ", ") + std::string(p.name);
  throw Error("unknown material preset '" + name + "' (known presets: " + known + ")");
}

std::vector<std::string> material_preset_names() {
  std::vector<std::string> names;
  names.reserve(kPresets.size());
  for (const Preset& p : kPresets) names.emplace_back(p.name);
  return names;
}

}  // namespace trocar
