#include "trocar/tissue/settings.h"

#include <cmath>
#include <numeric>
#include <string>

#include "trocar/core/error.h"
#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

void check_material(const MassSpringMaterial& m) {
  const auto require = [](Real value, const char* name) {
    if (!(value >= 0) || !std::isfinite(value))
      throw Error(std::string("material.") + name + ": must be a finite number >= 0");
  };
  require(m.mass, "mass");
  require(m.density, "density");
  require(m.sheet_thickness, "sheet_thickness");
  require(m.k_structural, "k_structural");
  require(m.k_bending, "k_bending");
  require(m.damping, "damping");
  require(m.spring_damping, "spring_damping");
  require(m.k_area, "k_area");
  require(m.k_volume, "k_volume");
  require(m.k_home, "k_home");
  require(m.home_yield, "home_yield");
  if (m.mass == 0 && m.density == 0) throw Error("material: mass or density must be > 0");
}

bool is_fixed(const Vec3& x, std::uint32_t index, const FixedSelection& f, const std::vector<std::uint8_t>& listed) {
  if (listed[index]) return true;
  if (f.below_plane && f.below_plane->normal.dot(x - f.below_plane->point) < 0) return true;
  if (f.inside_box && f.inside_box->contains(x)) return true;
  return false;
}

}  // namespace

MassSpringSettings MassSpringSettings::build(const TriMesh& mesh, const MassSpringMaterial& material,
                                             const FixedSelection& fixed, const Vec3& gravity) {
  if (mesh.triangles.empty()) throw Error("tissue mesh has no triangles");
  if (!mesh.indices_valid()) throw Error("tissue mesh has a triangle index out of range");
  for (const Vec3& p : mesh.positions)
    if (!p.allFinite()) throw Error("tissue mesh has a non-finite vertex position");
  check_material(material);

  const std::size_t n = mesh.vertex_count();
  const MeshTopology topology(mesh);
  MassSpringSettings s;
  s.triangles = mesh.triangles;
  s.rest_positions = mesh.positions;
  s.home_positions = mesh.positions;
  s.k_area = material.k_area;
  s.k_volume = material.k_volume;
  s.k_home = material.k_home;
  s.home_yield = material.home_yield;
  s.damping = material.damping;
  s.gravity = gravity;

  // Springs: structural on every edge, then bending across every interior edge (the two
  // vertices opposite the edge), as in Provot 1995 and the seed's Fig. 3.3.
  s.springs.reserve(2 * topology.edge_count());
  for (const Edge& e : topology.edges()) {
    const Real rest = (mesh.positions[e.v1] - mesh.positions[e.v0]).norm();
    s.springs.push_back({e.v0, e.v1, rest, material.k_structural, material.spring_damping});
  }
  s.structural_count = s.springs.size();
  if (material.k_bending > 0) {
    for (std::size_t e = 0; e < topology.edge_count(); ++e) {
      const auto [a, b] = topology.opposite_vertices(e);
      if (a == MeshTopology::kNone || b == MeshTopology::kNone || a == b) continue;
      const Real rest = (mesh.positions[b] - mesh.positions[a]).norm();
      s.springs.push_back({std::min(a, b), std::max(a, b), rest, material.k_bending, material.spring_damping});
    }
  }

  // Areas, volume, closedness.
  s.rest_areas.resize(mesh.triangle_count());
  Real area_sum = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    s.rest_areas[t] = 0.5 * mesh.triangle_normal_area2(t).norm();
    area_sum += s.rest_areas[t];
  }
  s.mean_rest_area = area_sum / static_cast<Real>(mesh.triangle_count());
  s.closed = topology.boundary_edges().empty() && topology.nonmanifold_edges().empty();
  s.rest_volume = s.closed ? mesh.signed_volume() : 0;
  if (s.closed && !(s.rest_volume > 0)) s.closed = false;  // inside-out or flat: no volume term

  // Mass lumped by area: each triangle gives a third of its area to each corner.
  Real total_mass = material.mass;
  if (total_mass == 0)
    total_mass = s.closed ? material.density * s.rest_volume : material.density * area_sum * material.sheet_thickness;
  if (!(total_mass > 0)) throw Error("tissue mass is zero (zero area or volume with a density)");
  std::vector<Real> share(n, 0.0);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
    for (std::uint32_t v : mesh.triangles[t]) share[v] += s.rest_areas[t] / 3.0;
  s.masses.resize(n);
  s.inverse_masses.resize(n);
  s.fixed.assign(n, 0);
  std::vector<std::uint8_t> listed(n, 0);
  for (std::uint32_t i : fixed.indices) {
    if (i >= n) throw Error("fixed vertex index " + std::to_string(i) + " is out of range (mesh has " + std::to_string(n) + " vertices)");
    listed[i] = 1;
  }
  // Vertices no triangle uses get a tiny share so they stay finite; they have no forces.
  const Real fallback = total_mass / static_cast<Real>(n) * 1e-6;
  for (std::size_t i = 0; i < n; ++i) {
    s.masses[i] = share[i] > 0 ? total_mass * share[i] / area_sum : fallback;
    s.fixed[i] = is_fixed(mesh.positions[i], static_cast<std::uint32_t>(i), fixed, listed) ? 1 : 0;
    s.inverse_masses[i] = s.fixed[i] ? 0.0 : 1.0 / s.masses[i];
  }
  return s;
}

Real MassSpringSettings::total_mass() const { return std::accumulate(masses.begin(), masses.end(), Real{0}); }

}  // namespace trocar
