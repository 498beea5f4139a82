#pragma once
/// Material of a mass-spring tissue: stiffnesses, damping, mass, and which vertices are fixed.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "trocar/core/aabb.h"
#include "trocar/core/types.h"

namespace trocar {

/// Per-tissue material, in SI units (scene key `material`, docs/tissue.md "Material fields and
/// their units"). Stiffnesses are per spring or per constraint, not per unit length, so they mean
/// the same on any mesh resolution only roughly: docs/tissue.md says how to choose them.
struct MassSpringMaterial {
  Real mass = 0;                  ///< total mass (kg); used when > 0, else from density
  Real density = 1060;            ///< kg/m³ (soft tissue ≈ 1060); closed: × volume
  Real sheet_thickness = 0.002;   ///< m; open surfaces: mass = density × area × thickness
  Real k_structural = 300;        ///< N/m, spring on every unique edge
  Real k_bending = 30;            ///< N/m, spring across every interior edge (flexion)
  Real damping = 0.5;             ///< γ of eq. 3.1 as a rate (1/s): force −γ·m_i·v_i
  Real spring_damping = 0.05;     ///< λ of eq. 3.2 (N·s/m), along each spring
  Real k_area = 0;                ///< N/m: energy ½·k_area·(A−A0)²/Ā0 per triangle
  Real k_volume = 0;              ///< Pa: energy ½·k_volume·(V−V0)²/V0 (closed meshes only)
  Real k_home = 0;                ///< N/m: spring from each vertex to its rest position
  /// m: the home springs' yield (0: elastic). Stretched further, a vertex's anchor follows it to
  /// this distance (perfect plasticity): attachments that give under traction, so that a hernia
  /// sac drawn back stays back, within this distance of where it was let go (docs/tissue.md).
  Real home_yield = 0;
};

/// A half-space n·(x − point) < 0 ("below the plane"); normal need not be unit.
struct Plane {
  Vec3 point = Vec3::Zero();   ///< a point on the plane (m)
  Vec3 normal = Vec3::UnitZ(); ///< the side a vertex must be on to stay free
};

/// Which vertices never move: the union of the three selections.
struct FixedSelection {
  std::vector<std::uint32_t> indices;  ///< explicit vertex indices
  std::optional<Plane> below_plane;    ///< every vertex with n·(x − p) < 0
  std::optional<Aabb> inside_box;      ///< every vertex inside the box
};

/// Named presets tuned so each shared organ (scaled to metres) holds its shape under gravity
/// at dt = 1 ms within a few millimetres (see docs/tissue.md and tests/tissue/preset_test).
/// Known names: "liver", "gallbladder", "abdominal_wall", "stomach", "peritoneum", "soft", "polypropylene-mesh" (a prosthetic
/// hernia mesh, not an organ: tests/response/tissue_contact_test.cpp uses it).
/// Throws trocar::Error for an unknown name.
MassSpringMaterial material_preset(const std::string& name);
/// The names material_preset() knows.
std::vector<std::string> material_preset_names();

}  // namespace trocar
