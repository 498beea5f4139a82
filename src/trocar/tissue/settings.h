#pragma once
/// Immutable mass-spring model built once from a surface mesh (Jolt's "shared settings").
#include <cstdint>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"
#include "trocar/tissue/material.h"

namespace trocar {

/// One spring: a plain struct in a flat array (hot data, 32 bytes).
struct Spring {
  std::uint32_t i = 0;       ///< first vertex
  std::uint32_t j = 0;       ///< second vertex
  Real rest_length = 0;      ///< l_ij (m)
  Real stiffness = 0;        ///< k_ij (N/m)
  Real damping = 0;          ///< λ_ij (N·s/m), along the spring
};

/// Topology, rest state, masses and stiffnesses of one tissue. Built once; never changes
/// during a simulation (so any number of MassSpringState instances can share it), except the
/// home anchors of a tissue with a home yield (yield_home()).
struct MassSpringSettings {
  std::vector<Spring> springs;           ///< structural springs first, then bending springs
  std::size_t structural_count = 0;      ///< springs[0, structural_count) are on mesh edges
  std::vector<Triangle> triangles;       ///< the surface (for area, volume and contacts)
  std::vector<Real> rest_areas;          ///< A0 per triangle (m²)
  Real mean_rest_area = 0;               ///< Ā0 (m²), normalises the area term
  bool closed = false;                   ///< volume term applies only to closed meshes
  Real rest_volume = 0;                  ///< V0 (m³), signed volume at rest
  std::vector<Vec3> rest_positions;      ///< x0 per vertex (m): the shape at rest
  std::vector<Vec3> home_positions;      ///< the home springs' anchors (m): x0 until they yield
  std::vector<Real> masses;              ///< m_i (kg), lumped by adjacent area
  std::vector<Real> inverse_masses;      ///< 1/m_i, 0 for fixed vertices
  std::vector<std::uint8_t> fixed;       ///< 1 when the vertex never moves
  Real k_area = 0;                       ///< N/m
  Real k_volume = 0;                     ///< Pa
  Real k_home = 0;                       ///< N/m
  Real home_yield = 0;                   ///< m, 0: elastic (MassSpringMaterial::home_yield)
  Real damping = 0;                      ///< γ (1/s)
  Vec3 gravity = Vec3::Zero();           ///< m/s²

  /// Builds the model from a mesh already in metres. Springs: one per unique edge
  /// (k_structural) and one per interior edge between the two opposite vertices
  /// (k_bending). Mass: material.mass if > 0, else density × volume (closed) or
  /// density × area × thickness (open), lumped to vertices by one third of each adjacent
  /// triangle's area. Throws trocar::Error for an empty mesh, bad indices or a negative
  /// material value.
  static MassSpringSettings build(const TriMesh& mesh, const MassSpringMaterial& material,
                                  const FixedSelection& fixed = {}, const Vec3& gravity = Vec3::Zero());

  std::size_t vertex_count() const { return masses.size(); }   ///< V
  Real total_mass() const;                                     ///< Σ m_i (kg)
};

}  // namespace trocar
static_assert(sizeof(trocar::Spring) == 32, "Spring is hot data: keep it 32 bytes");
