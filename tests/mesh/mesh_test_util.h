#pragma once
// Small meshes made in code for the topology/validate/repair tests.
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

}  // namespace trocar::test
