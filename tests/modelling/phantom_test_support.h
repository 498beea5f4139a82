#pragma once
// Helpers of the modelling tests: the distance of a point to an analytic surface, and the
// volume centroid of a closed mesh.
#include "trocar/mesh/tri_mesh.h"

namespace trocar::test {

/// Centroid of the solid a closed outward mesh encloses: Σ centroid·volume of the tetrahedra
/// (origin, a, b, c), divided by the total volume.
inline Vec3 solid_centroid(const TriMesh& mesh) {
  Vec3 sum = Vec3::Zero();
  Real volume = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const auto c = mesh.corners(t);
    const Real v = c[0].dot(c[1].cross(c[2])) / 6;
    sum += v * (c[0] + c[1] + c[2]) / 4;
    volume += v;
  }
  return sum / volume;
}

}  // namespace trocar::test
