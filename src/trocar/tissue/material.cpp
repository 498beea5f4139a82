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

// How to read the numbers (per spring / per constraint, SI; docs/tissue.md has the reasoning):
//  * Support. A vertex of mass m held by its home spring alone sags m·g/k_home. Every organ
//    preset sets k_home so that the mean vertex's home-spring sag is below 0.5 mm; the springs
//    and the volume term share the load with the fixed region, so the organ as a whole sags
//    about a millimetre or less (tests/tissue/preset_test.cpp measures it).
//  * Stability. Explicit and semi-implicit Euler need h²·Σk/m ≲ 4 at the lightest vertex
//    (Σk: its springs' stiffnesses plus k_home). At h = 1 ms the shared organs' lightest vertices
//    (0.1 mg to 0.1 g: sliver triangles get little area) allow 0.1 to 20 N/m per spring: far too
//    soft to carry an organ, so every organ preset is meant for implicit-euler.
//  * Cost. The implicit step's conjugate-gradient iterations grow like √(h²·k/m̄) (m̄: mean
//    vertex mass), so each organ's k_structural is the softest that keeps the organ's shape
//    (within about 1 mm under gravity with its support); k_bending = k_structural/10.
//  * k_area = 0 everywhere: structural springs on all three edges already fix each triangle's
//    shape, hence its area, and the area term costs a third of a force evaluation (and, in the
//    implicit step, a triangle pass per CG iteration). Use it when k_structural is small.
//  * Damping. γ = 5/s (the surrounding tissue and fluid; relaxation time 0.2 s); λ about
//    0.1·√(k·m̄), well under critical.
constexpr std::array<Preset, 7> kPresets{{
    // Liver, 1.5 kg (adult liver 1.2–1.8 kg). Shared mesh: liver_sofa_smooth.obj × 0.01
    // (6.4 cm wide, so this is a dense load case), 2194 V, mean vertex 0.68 g, lightest 0.09 g.
    // Closed: the volume term is a bulk modulus (Pa).
    {"liver", "implicit-euler",
     {.mass = 1.5, .density = 1060, .sheet_thickness = 0.002, .k_structural = 150, .k_bending = 15,
      .damping = 5, .spring_damping = 0.03, .k_area = 0, .k_volume = 2e4, .k_home = 30}},
    // Gallbladder with bile, 70 g (typically 50–100 g). Shared mesh: gallbladder_lapgym.stl ×
    // 0.001, 7352 V, mean vertex 9.5 mg, lightest 0.2 mg. The bile is the volume term.
    {"gallbladder", "implicit-euler",
     {.mass = 0.07, .density = 1060, .sheet_thickness = 0.002, .k_structural = 10, .k_bending = 1,
      .damping = 5, .spring_damping = 0.002, .k_area = 0, .k_volume = 5e3, .k_home = 1}},
    // Abdominal wall (skin, fat, muscle), 1.6 kg (density × the shared shell's 1.55 L). Shared
    // mesh: abdominal_wall_openhelp.stl × 0.001, a closed thick shell, 15969 V, mean vertex
    // 0.1 g, lightest 0.12 mg.
    {"abdominal_wall", "implicit-euler",
     {.mass = 1.6, .density = 1060, .sheet_thickness = 0.01, .k_structural = 50, .k_bending = 5,
      .damping = 5, .spring_damping = 0.005, .k_area = 0, .k_volume = 1e4, .k_home = 10}},
    // Empty stomach, 150 g. Shared mesh: stomach_bodyparts3d_FMA7148.obj × 0.001, 4694 V,
    // mean vertex 32 mg, lightest 1 mg. Hollow: the volume term stands for its gas and content.
    {"stomach", "implicit-euler",
     {.mass = 0.15, .density = 1060, .sheet_thickness = 0.003, .k_structural = 30, .k_bending = 3,
      .damping = 5, .spring_damping = 0.005, .k_area = 0, .k_volume = 5e3, .k_home = 3}},
    // Peritoneum: a thin open sheet (0.5 mm with its fluid film), mass from density × area ×
    // thickness (a 20 × 20 cm sheet: 21 g). Flexible (weak bending); held at its border and by
    // home springs. No volume term (open).
    {"peritoneum", "implicit-euler",
     {.mass = 0, .density = 1060, .sheet_thickness = 5e-4, .k_structural = 20, .k_bending = 0.5,
      .damping = 5, .spring_damping = 0.002, .k_area = 0, .k_volume = 0, .k_home = 2}},
    // Generic soft tissue: mass from density × volume (closed) or × area × 2 mm (open). Meant
    // for semi-implicit-euler on coarse meshes, vertex mass ≳ 50 mg (4·m/h² = 200 N/m against
    // Σk ≈ 6·20 + 6·2 + 2 = 134 N/m); use implicit-euler on finer meshes.
    {"soft", "semi-implicit-euler",
     {.mass = 0, .density = 1060, .sheet_thickness = 0.002, .k_structural = 20, .k_bending = 2,
      .damping = 5, .spring_damping = 0.02, .k_area = 0, .k_volume = 1e3, .k_home = 2}},
    // Lightweight polypropylene hernia mesh (docs/tissue.md, "polypropylene-mesh"): 40 g/m²
    // (lightweight meshes 28–60 g/m², Deveci et al. 2023; Parietene Light / Optilene 36–48 g/m²,
    // Brown & Finch 2010) as an effective density over a 0.5 mm knit. Tensile: 16 N/cm (the
    // groin's physiological load, Zhu, Schuster & Klinge 2015) stretches it by an assumed 20 %,
    // a membrane stiffness of 8 kN/m; on a square grid with one diagonal per cell the springs
    // carry 1.5·k per unit width, so k_structural = 8000/1.5 ≈ 5300 N/m on any grid spacing.
    // A floppy knit: k_bending 0.05 N/m. Free: no home springs; open: no volume term.
    {"polypropylene-mesh", "implicit-euler",
     {.mass = 0, .density = 80, .sheet_thickness = 5e-4, .k_structural = 5300, .k_bending = 0.05,
      .damping = 2, .spring_damping = 0.005, .k_area = 0, .k_volume = 0, .k_home = 0}},
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
