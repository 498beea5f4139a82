#pragma once
/// Signed distance to a closed triangle mesh with angle-weighted pseudonormals.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/geometry/aabb_tree.h"
#include "trocar/geometry/closest_point.h"

namespace trocar {

/// Result of a signed-distance query.
struct SignedDistanceResult {
  /// Signed distance to the surface (mesh unit, metres): negative inside, positive outside,
  /// 0 on the surface; +infinity for a mesh without triangles.
  Real distance = std::numeric_limits<Real>::infinity();
  Vec3 closest_point = Vec3::Zero();  ///< the surface point nearest to the query
  /// Index of the triangle holding closest_point (kNoTriangle for an empty mesh). On ties (a
  /// point equally near several triangles) any of them; the distance and sign do not depend on it.
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();
  TriangleFeature feature = TriangleFeature::kFace;  ///< face, edge or vertex of that triangle
  int feature_index = 0;                             ///< edge k or vertex k of that triangle
  Vec3 pseudonormal = Vec3::Zero();  ///< unit outward pseudonormal of the feature (0 if none)
};

/// Signed distance to a closed, consistently oriented triangle mesh (counter-clockwise seen
/// from outside, so (b−a)×(c−a) points out; Triangle in core/types.h).
///
/// The sign follows Bærentzen & Aanæs, "Signed distance computation using the angle weighted
/// pseudonormal", IEEE TVCG 11(3), 2005: with c the closest surface point and n the
/// pseudonormal of the feature c lies on — the face normal in a face, the sum of the two
/// adjacent face normals on an edge, the sum of incident face normals weighted by their angle at
/// the vertex on a vertex — p is outside iff (p − c)·n ≥ 0. This is exact for closed 2-manifold
/// meshes (their Theorem 1). Boundary edges use their one face normal, non-manifold edges the
/// sum of all their faces; the sign there is not meaningful (open meshes have no inside).
///
/// Closest points come from an AabbTree over the triangles (built once); refit() takes new
/// vertex positions (same count and topology) for a deforming mesh, recomputing normals,
/// pseudonormals and boxes without allocating. Queries do not allocate.
class MeshDistance {
 public:
  /// Value of SignedDistanceResult::triangle when the mesh is empty.
  static constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

  /// Copies the mesh, builds its edge map (sorted vertex pairs), normals and tree. Throws
  /// trocar::Error when a triangle refers to a vertex that does not exist.
  MeshDistance(std::span<const Vec3> positions, std::span<const Triangle> triangles);

  /// New vertex positions for the same triangles (throws trocar::Error on a count mismatch).
  void refit(std::span<const Vec3> positions);

  /// Signed distance from p, using the tree.
  SignedDistanceResult signed_distance(const Vec3& p) const;
  /// Same as signed_distance() by testing every triangle (a reference for tests; O(n)).
  SignedDistanceResult signed_distance_brute_force(const Vec3& p) const;

  std::span<const Vec3> positions() const { return positions_; }      ///< current vertices
  std::span<const Triangle> triangles() const { return triangles_; }  ///< the triangles
  /// Unit normal of triangle t (zero for a degenerate triangle).
  const Vec3& face_normal(std::uint32_t t) const { return face_normals_[t]; }
  /// Unit angle-weighted pseudonormal of vertex v (zero for an unused vertex).
  const Vec3& vertex_pseudonormal(std::uint32_t v) const { return vertex_normals_[v]; }
  /// Unit pseudonormal of edge k (vertex k → k+1) of triangle t.
  const Vec3& edge_pseudonormal(std::uint32_t t, int k) const {
    return edge_normals_[edge_of_slot_[3 * t + static_cast<std::uint32_t>(k)]];
  }
  /// Number of distinct edges found (a closed manifold mesh has 3/2 per triangle).
  std::size_t edge_count() const { return edge_normals_.size(); }
  /// The triangle tree.
  const AabbTree& tree() const { return tree_; }

 private:
  void update_normals();
  void update_boxes();
  SignedDistanceResult finish(const Vec3& p, std::uint32_t t, const TriangleClosestPoint& c,
                              Real d2) const;

  std::vector<Vec3> positions_;
  std::vector<Triangle> triangles_;
  std::vector<Vec3> face_normals_;
  std::vector<Vec3> vertex_normals_;
  std::vector<std::uint32_t> edge_of_slot_;  // 3t + k → edge id
  std::vector<Vec3> edge_normals_;
  std::vector<Aabb> boxes_;
  AabbTree tree_;
};

}  // namespace trocar
