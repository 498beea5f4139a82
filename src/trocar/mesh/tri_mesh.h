#pragma once
/// Indexed triangle surface mesh: the organs' and instruments' geometry.
#include <array>
#include <cstdint>
#include <vector>

#include "trocar/core/aabb.h"
#include "trocar/core/types.h"

namespace trocar {

/// A triangle mesh. Positions are contiguous (std::vector<Vec3> is a flat array of doubles);
/// triangles index into them. Attributes are optional: `normals` is empty or one per vertex;
/// `texcoords` is empty or one per triangle corner (3 per triangle, corner order as in
/// `triangles`), so that texture seams need no split vertices and the topology stays that of
/// the surface.
struct TriMesh {
  std::vector<Vec3> positions;      ///< vertex positions (file units until a scene scales them)
  std::vector<Triangle> triangles;  ///< vertex index triplets
  std::vector<Vec3> normals;        ///< optional per-vertex unit normals (empty if none)
  std::vector<Vec2> texcoords;      ///< optional per-corner (u, v), size 3·triangles (or empty)

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }

  /// Bounding box of all positions (used or not).
  Aabb bounds() const;
  /// Total surface area Σ ½|(b−a)×(c−a)|.
  Real area() const;
  /// Signed enclosed volume Σ a·(b×c)/6 (divergence theorem); positive when a closed mesh's
  /// normals point outward. Meaningless for open surfaces.
  Real signed_volume() const;
  /// Unnormalised normal (b−a)×(c−a) of triangle t (its length is twice the area).
  Vec3 triangle_normal_area2(std::size_t t) const;
  /// Corner positions of triangle t.
  std::array<Vec3, 3> corners(std::size_t t) const {
    const Triangle& tri = triangles[t];
    return {positions[tri[0]], positions[tri[1]], positions[tri[2]]};
  }
  /// True when every index is < vertex_count() and the attribute arrays have valid sizes.
  bool indices_valid() const;
  /// Applies x ← scale·x to positions (normals unchanged).
  void scale(Real factor);
};

}  // namespace trocar
