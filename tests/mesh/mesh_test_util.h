#pragma once
// Small meshes made in code for the topology/validate/repair tests, and shared measurements.
#include <algorithm>
#include <limits>

#include "trocar/mesh/tri_mesh.h"

namespace trocar::test {

/// Regular-ish tetrahedron, outward: 4 V, 4 T, 6 E.
inline TriMesh tetrahedron() {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

/// Unit cube [0,1]³, outward: 8 V, 12 T, 18 E (corner i = x + 2y + 4z).
inline TriMesh unit_cube() {
  TriMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0);
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

/// Smallest distance from the origin to a triangle's plane over all triangles. A closed mesh
/// whose triangles all face away from the origin and whose cones over them tile the directions
/// (a convex polyhedron round the origin, a star-shaped organ) contains the ball of that radius,
/// so its volume is ≥ 4/3·π·d³; a convex one also has area ≥ 4π·d² (a convex body containing
/// another has the larger surface area).
inline Real min_plane_distance(const TriMesh& m) {
  Real d = std::numeric_limits<Real>::infinity();
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Vec3 n = m.triangle_normal_area2(t).normalized();
    d = std::min(d, n.dot(m.positions[m.triangles[t][0]]));
  }
  return d;
}

}  // namespace trocar::test
