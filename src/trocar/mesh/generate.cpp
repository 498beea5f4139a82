#include "trocar/mesh/generate.h"

#include <cmath>
#include <numbers>
#include <string>

#include "trocar/core/error.h"
#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

void require(bool ok, const char* what) {
  if (!ok) throw Error(std::string("mesh generator: ") + what);
}

std::uint32_t u32(std::size_t i) { return static_cast<std::uint32_t>(i); }

/// Adds a ring of `segments` points of radius `r` at height z, angle 2πi/segments.
void add_ring(TriMesh& mesh, Real r, Real z, std::size_t segments) {
  for (std::size_t i = 0; i < segments; ++i) {
    const Real a = 2 * kPi * static_cast<Real>(i) / static_cast<Real>(segments);
    mesh.positions.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
}

/// Quads between ring `lo` and ring `hi` (first vertex indices), outward for lo below hi:
/// (l_i, l_{i+1}, h_{i+1}) and (l_i, h_{i+1}, h_i); the tangent ×  up is radial.
void add_band(TriMesh& mesh, std::size_t lo, std::size_t hi, std::size_t segments) {
  for (std::size_t i = 0; i < segments; ++i) {
    const std::size_t j = (i + 1) % segments;
    mesh.triangles.push_back({u32(lo + i), u32(lo + j), u32(hi + j)});
    mesh.triangles.push_back({u32(lo + i), u32(hi + j), u32(hi + i)});
  }
}

/// Fan from `center` to the ring at `ring`: facing −z when `down`, else +z.
void add_fan(TriMesh& mesh, std::size_t center, std::size_t ring, std::size_t segments, bool down) {
  for (std::size_t i = 0; i < segments; ++i) {
    const std::size_t j = (i + 1) % segments;
    if (down)
      mesh.triangles.push_back({u32(center), u32(ring + j), u32(ring + i)});
    else
      mesh.triangles.push_back({u32(center), u32(ring + i), u32(ring + j)});
  }
}

}  // namespace

TriMesh make_icosphere(Real radius, int subdivisions) {
  require(radius > 0 && std::isfinite(radius), "icosphere radius must be positive");
  require(subdivisions >= 0 && subdivisions <= 10, "icosphere subdivisions must be in [0, 10]");
  const Real phi = (1 + std::sqrt(5.0)) / 2;
  TriMesh mesh;
  // The 12 vertices (0, ±1, ±φ) and its cyclic permutations; the 20 faces of the standard
  // icosahedron, each then turned so its normal points away from the centre.
  const Real c[12][3] = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                         {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                         {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  for (const auto& p : c) mesh.positions.push_back(Vec3(p[0], p[1], p[2]).normalized());
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Triangle& tri : mesh.triangles) {
    const Vec3 centroid = mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]];
    if (mesh.triangle_normal_area2(static_cast<std::size_t>(&tri - mesh.triangles.data())).dot(centroid) < 0)
      std::swap(tri[1], tri[2]);
  }
  // Each level: one new vertex per edge (its midpoint pushed onto the unit sphere), each
  // triangle (a, b, c) with edge midpoints m0 = ab, m1 = bc, m2 = ca → four triangles wound
  // as the parent.
  for (int level = 0; level < subdivisions; ++level) {
    const MeshTopology topo(mesh);
    const std::size_t base = mesh.positions.size();
    for (const Edge& e : topo.edges())
      mesh.positions.push_back((mesh.positions[e.v0] + mesh.positions[e.v1]).normalized());
    std::vector<Triangle> next;
    next.reserve(4 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      const auto& te = topo.triangle_edges(t);
      const std::uint32_t m0 = u32(base + te[0]), m1 = u32(base + te[1]), m2 = u32(base + te[2]);
      next.push_back({tri[0], m0, m2});
      next.push_back({m0, tri[1], m1});
      next.push_back({m2, m1, tri[2]});
      next.push_back({m0, m1, m2});
    }
    mesh.triangles = std::move(next);
  }
  mesh.normals = mesh.positions;  // unit vectors from the centre
  for (Vec3& p : mesh.positions) p *= radius;
  return mesh;
}

TriMesh make_sheet(Real width, Real height, std::size_t nx, std::size_t ny, Real bulge_height) {
  require(width > 0 && height > 0 && std::isfinite(width) && std::isfinite(height), "sheet size must be positive");
  require(nx >= 1 && ny >= 1, "sheet needs at least one cell each way");
  require(std::isfinite(bulge_height), "sheet bulge must be finite");
  require((nx + 1) * (ny + 1) < MeshTopology::kNone, "sheet too fine");
  TriMesh mesh;
  mesh.positions.reserve((nx + 1) * (ny + 1));
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i <= nx; ++i) {
      const Real x = width * (static_cast<Real>(i) / static_cast<Real>(nx) - 0.5);
      const Real y = height * (static_cast<Real>(j) / static_cast<Real>(ny) - 0.5);
      // cos² bump: 0 with zero slope on the border, bulge_height at the centre.
      const Real cx = std::cos(kPi * x / width), cy = std::cos(kPi * y / height);
      mesh.positions.emplace_back(x, y, bulge_height * cx * cx * cy * cy);
    }
  // The border rows give cos(±π/2) ≈ 6e−17, not 0: pin them so the border is exactly flat.
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i <= nx; ++i)
      if (i == 0 || j == 0 || i == nx || j == ny) mesh.positions[j * (nx + 1) + i].z() = 0;
  mesh.triangles.reserve(2 * nx * ny);
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::uint32_t v00 = u32(j * (nx + 1) + i), v10 = v00 + 1;
      const std::uint32_t v01 = u32(v00 + nx + 1), v11 = v01 + 1;
      if ((i + j) % 2 == 0) {  // diagonal v00–v11
        mesh.triangles.push_back({v00, v10, v11});
        mesh.triangles.push_back({v00, v11, v01});
      } else {  // diagonal v10–v01
        mesh.triangles.push_back({v00, v10, v01});
        mesh.triangles.push_back({v10, v11, v01});
      }
    }
  return mesh;
}

TriMesh make_capsule(Real radius, Real length, std::size_t segments, std::size_t rings) {
  require(radius > 0 && std::isfinite(radius), "capsule radius must be positive");
  require(length > 0 && std::isfinite(length), "capsule length must be positive (use make_icosphere for a sphere)");
  require(segments >= 3 && rings >= 1, "capsule needs segments >= 3 and rings >= 1");
  TriMesh mesh;
  mesh.positions.emplace_back(0, 0, -radius);  // south pole, index 0
  // 2·rings circles from bottom to top: latitudes −π/2 + (π/2)k/rings, k = 1..rings, about
  // z = 0, then (π/2)k/rings, k = 0..rings−1, about z = length.
  for (std::size_t k = 1; k <= rings; ++k) {
    const Real lat = -kPi / 2 + kPi / 2 * static_cast<Real>(k) / static_cast<Real>(rings);
    add_ring(mesh, radius * std::cos(lat), radius * std::sin(lat), segments);
  }
  for (std::size_t k = 0; k < rings; ++k) {
    const Real lat = kPi / 2 * static_cast<Real>(k) / static_cast<Real>(rings);
    add_ring(mesh, radius * std::cos(lat), length + radius * std::sin(lat), segments);
  }
  const std::size_t north = mesh.positions.size();
  mesh.positions.emplace_back(0, 0, length + radius);
  add_fan(mesh, 0, 1, segments, true);
  for (std::size_t c = 0; c + 1 < 2 * rings; ++c) add_band(mesh, 1 + c * segments, 1 + (c + 1) * segments, segments);
  add_fan(mesh, north, 1 + (2 * rings - 1) * segments, segments, false);
  return mesh;
}

TriMesh make_cylinder(Real radius, Real length, std::size_t segments, bool capped) {
  require(radius > 0 && std::isfinite(radius), "cylinder radius must be positive");
  require(length > 0 && std::isfinite(length), "cylinder length must be positive");
  require(segments >= 3, "cylinder needs segments >= 3");
  TriMesh mesh;
  add_ring(mesh, radius, 0, segments);       // 0 .. s−1
  add_ring(mesh, radius, length, segments);  // s .. 2s−1
  add_band(mesh, 0, segments, segments);
  if (capped) {
    mesh.positions.emplace_back(0, 0, 0);
    mesh.positions.emplace_back(0, 0, length);
    add_fan(mesh, 2 * segments, 0, segments, true);
    add_fan(mesh, 2 * segments + 1, segments, segments, false);
  }
  return mesh;
}

TriMesh make_box(Real sx, Real sy, Real sz) {
  require(sx > 0 && sy > 0 && sz > 0 && std::isfinite(sx) && std::isfinite(sy) && std::isfinite(sz),
          "box sizes must be positive");
  TriMesh mesh;
  // Corner i = x + 2y + 4z (bits select the − or + side of each axis).
  for (int i = 0; i < 8; ++i)
    mesh.positions.emplace_back((i & 1 ? 0.5 : -0.5) * sx, (i & 2 ? 0.5 : -0.5) * sy, (i & 4 ? 0.5 : -0.5) * sz);
  mesh.triangles = {{0, 2, 3}, {0, 3, 1},   // −z
                    {4, 5, 7}, {4, 7, 6},   // +z
                    {0, 1, 5}, {0, 5, 4},   // −y
                    {2, 6, 7}, {2, 7, 3},   // +y
                    {0, 4, 6}, {0, 6, 2},   // −x
                    {1, 3, 7}, {1, 7, 5}};  // +x
  return mesh;
}

}  // namespace trocar
