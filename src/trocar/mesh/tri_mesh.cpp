#include "trocar/mesh/tri_mesh.h"

namespace trocar {

Aabb TriMesh::bounds() const { return Aabb::of_points(positions); }

Vec3 TriMesh::triangle_normal_area2(std::size_t t) const {
  const auto [a, b, c] = corners(t);
  return (b - a).cross(c - a);
}

Real TriMesh::area() const {
  Real sum = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t) sum += 0.5 * triangle_normal_area2(t).norm();
  return sum;
}

Real TriMesh::signed_volume() const {
  // Translating to the bounding-box centre first keeps the sum accurate for meshes far from
  // the origin (BodyParts3D organs sit about 1 m away), where a·(b×c) would cancel badly.
  const Vec3 origin = bounds().is_empty() ? Vec3::Zero() : bounds().center();
  Real sum = 0;
  for (const Triangle& tri : triangles) {
    const Vec3 a = positions[tri[0]] - origin;
    const Vec3 b = positions[tri[1]] - origin;
    const Vec3 c = positions[tri[2]] - origin;
    sum += a.dot(b.cross(c));
  }
  return sum / 6.0;
}

bool TriMesh::indices_valid() const {
  const std::size_t n = positions.size();
  for (const Triangle& tri : triangles)
    for (std::uint32_t i : tri)
      if (i >= n) return false;
  if (!normals.empty() && normals.size() != n) return false;
  if (!texcoords.empty() && texcoords.size() != 3 * triangles.size()) return false;
  return true;
}

void TriMesh::scale(Real factor) {
  for (Vec3& p : positions) p *= factor;
}

}  // namespace trocar
