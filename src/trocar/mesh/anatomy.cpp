#include "trocar/mesh/anatomy.h"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

void require(bool ok, const char* what) {
  if (!ok) throw Error(std::string("anatomy generator: ") + what);
}

bool positive(Real x) { return x > 0 && std::isfinite(x); }

std::uint32_t u32(std::size_t i) { return static_cast<std::uint32_t>(i); }

/// `segments` points on the border of the w × h rectangle, counter-clockwise from the corner
/// (w/2, −h/2), segments/4 per side with every corner among them (z = 0).
std::vector<Vec3> rectangle_border(Real w, Real h, std::size_t segments) {
  const std::size_t q = segments / 4;
  std::vector<Vec3> border;
  border.reserve(segments);
  for (std::size_t side = 0; side < 4; ++side)
    for (std::size_t i = 0; i < q; ++i) {
      const Real s = static_cast<Real>(i) / static_cast<Real>(q);
      switch (side) {
        case 0: border.emplace_back(w / 2, -h / 2 + h * s, 0); break;
        case 1: border.emplace_back(w / 2 - w * s, h / 2, 0); break;
        case 2: border.emplace_back(-w / 2, h / 2 - h * s, 0); break;
        default: border.emplace_back(-w / 2 + w * s, -h / 2, 0); break;
      }
    }
  return border;
}

/// Ring m of the annulus between the circle of radius r (s = 0, at the border points'
/// angles) and the border (s = 1): r_i(s) = (1 − s)·r·d_i + s·b_i on the ray d_i = b_i/|b_i|.
void add_annulus_ring(TriMesh& mesh, const std::vector<Vec3>& border, Real r, Real s, Real z) {
  for (const Vec3& b : border) {
    const Vec3 p = (1 - s) * r * b.normalized() + s * b;
    mesh.positions.emplace_back(p.x(), p.y(), z);
  }
}

/// Triangles between ring `in` and the next ring `out` (first vertex indices), counter-clockwise
/// seen from +z for rings running counter-clockwise with `out` farther from the axis.
void add_planar_band(TriMesh& mesh, std::size_t in, std::size_t out, std::size_t segments, bool flip) {
  for (std::size_t i = 0; i < segments; ++i) {
    const std::size_t j = (i + 1) % segments;
    Triangle a{u32(in + i), u32(out + j), u32(in + j)};
    Triangle b{u32(in + i), u32(out + i), u32(out + j)};
    if (flip) {
      std::swap(a[1], a[2]);
      std::swap(b[1], b[2]);
    }
    mesh.triangles.push_back(a);
    mesh.triangles.push_back(b);
  }
}

void check_annulus(Real w, Real h, Real r, std::size_t segments, std::size_t rings) {
  require(positive(w) && positive(h), "sheet size must be positive");
  require(positive(r) && r < std::min(w, h) / 2, "opening radius must be in (0, min(width, height)/2)");
  require(segments >= 8 && segments % 4 == 0, "segments must be a multiple of 4, at least 8");
  require(rings >= 1, "need at least one ring");
  require(segments * (rings + 2) * 2 < 0xffffffffu, "mesh too fine");
}

}  // namespace

TriMesh make_hernia_peritoneum(Real width, Real height, Real sac_radius, Real sac_depth, std::size_t segments,
                               std::size_t sac_rings, std::size_t sheet_rings) {
  check_annulus(width, height, sac_radius, segments, sheet_rings);
  require(positive(sac_depth), "sac depth must be positive");
  require(sac_rings >= 1, "need at least one sac ring");
  const std::vector<Vec3> border = rectangle_border(width, height, segments);
  TriMesh mesh;
  mesh.positions.emplace_back(0, 0, sac_depth);  // apex, index 0
  // Sac rings k = 1..sac_rings at α = (π/2)·k/sac_rings: radius R·sin α, height depth·cos α.
  for (std::size_t k = 1; k <= sac_rings; ++k) {
    const Real a = kPi / 2 * static_cast<Real>(k) / static_cast<Real>(sac_rings);
    const Real z = k == sac_rings ? 0 : sac_depth * std::cos(a);  // the neck exactly at z = 0
    add_annulus_ring(mesh, border, sac_radius * std::sin(a), 0, z);
  }
  for (std::size_t m = 1; m <= sheet_rings; ++m)
    add_annulus_ring(mesh, border, sac_radius, static_cast<Real>(m) / static_cast<Real>(sheet_rings), 0);
  for (std::size_t i = 0; i < segments; ++i)  // fan at the apex, counter-clockwise from +z
    mesh.triangles.push_back({0, u32(1 + i), u32(1 + (i + 1) % segments)});
  const std::size_t rings = sac_rings + sheet_rings;
  for (std::size_t k = 0; k + 1 < rings; ++k) add_planar_band(mesh, 1 + k * segments, 1 + (k + 1) * segments, segments, false);
  return mesh;
}

TriMesh make_abdominal_wall(Real width, Real height, Real thickness, Real hole_radius, std::size_t segments,
                            std::size_t rings) {
  check_annulus(width, height, hole_radius, segments, rings);
  require(thickness >= 0 && std::isfinite(thickness), "wall thickness must be >= 0");
  const std::vector<Vec3> border = rectangle_border(width, height, segments);
  TriMesh mesh;
  const bool slab = thickness > 0;
  const std::size_t layers = slab ? 2 : 1;
  // Layer 0 (top, z = +t/2) then layer 1 (bottom, z = −t/2); rings m = 0 (hole) .. rings (border).
  for (std::size_t layer = 0; layer < layers; ++layer)
    for (std::size_t m = 0; m <= rings; ++m)
      add_annulus_ring(mesh, border, hole_radius, static_cast<Real>(m) / static_cast<Real>(rings),
                       slab ? (layer == 0 ? thickness / 2 : -thickness / 2) : 0);
  const std::size_t per_layer = segments * (rings + 1);
  for (std::size_t layer = 0; layer < layers; ++layer)
    for (std::size_t m = 0; m < rings; ++m)
      add_planar_band(mesh, layer * per_layer + m * segments, layer * per_layer + (m + 1) * segments, segments,
                      layer == 1);  // the bottom faces −z
  if (slab) {
    // Side walls: quads between the top and bottom copies of the hole ring and of the border
    // ring. The border's face outward (away from the axis), the hole's toward the axis.
    const std::size_t top_border = rings * segments, bottom_border = per_layer + rings * segments;
    const std::size_t top_hole = 0, bottom_hole = per_layer;
    for (std::size_t i = 0; i < segments; ++i) {
      const std::size_t j = (i + 1) % segments;
      mesh.triangles.push_back({u32(bottom_border + i), u32(bottom_border + j), u32(top_border + j)});
      mesh.triangles.push_back({u32(bottom_border + i), u32(top_border + j), u32(top_border + i)});
      mesh.triangles.push_back({u32(top_hole + i), u32(top_hole + j), u32(bottom_hole + j)});
      mesh.triangles.push_back({u32(top_hole + i), u32(bottom_hole + j), u32(bottom_hole + i)});
    }
  }
  return mesh;
}

TriMesh make_liver_lobe(Real length, Real width, Real thickness, int subdivisions, Real flatten, Real taper) {
  require(positive(length) && positive(width) && positive(thickness), "lobe sizes must be positive");
  require(flatten > 0 && flatten <= 1, "flatten must be in (0, 1]");
  require(taper >= 0 && taper < 1, "taper must be in [0, 1)");
  TriMesh mesh = make_icosphere(1.0, subdivisions);
  mesh.normals.clear();
  const Real a = length / 2, b = width / 2, c = thickness / 2;
  for (Vec3& p : mesh.positions) {
    // (x̂, ŷ, ẑ) on the unit sphere → (a·x̂, b·ŷ, c·g(x̂)·f(ẑ)·ẑ), g = 1 − taper·x̂ > 0 and
    // f = 1 above, `flatten` below: each vertical line through the lobe's outline keeps its
    // order, so the surface neither folds nor turns inside out.
    const Real z = p.z() < 0 ? flatten * p.z() : p.z();
    p = Vec3(a * p.x(), b * p.y(), c * (1 - taper * p.x()) * z);
  }
  return mesh;
}

}  // namespace trocar
