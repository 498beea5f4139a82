// Links every exported module and checks one value from each, so a broken export fails here.
#include <cstdio>

#include "trocar/core/aabb.h"
#include "trocar/mesh/tri_mesh.h"

int main() {
  trocar::TriMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const double volume = mesh.signed_volume();  // unit right tetrahedron: 1/6
  if (volume < 1.0 / 6 - 1e-12 || volume > 1.0 / 6 + 1e-12) return 1;
  std::printf("consumer: volume %.6f\n", volume);
  return 0;
}
