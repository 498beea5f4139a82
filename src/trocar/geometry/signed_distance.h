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
/// vertex positions (same count and topology) for a deforming mesh, recomputing the boxes
/// without allocating. Normals and pseudonormals are not stored: a query computes the one
/// pseudonormal its closest feature needs from the current positions (a face normal, the two
/// faces of an edge, the incident faces of a vertex, summed in ascending triangle order so the
/// result is the same bits as summing over all triangles). A refit therefore costs one pass
/// over the triangles' boxes instead of 3 atan2 per triangle, and a query a few more
/// cross products. Queries do not allocate.
class MeshDistance {
 public:
  /// Value of SignedDistanceResult::triangle when the mesh is empty.
  static constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

  /// Copies the mesh, builds its edge map (sorted vertex pairs), normals and tree. Throws
  /// trocar::Error when a triangle refers to a vertex that does not exist.
  MeshDistance(std::span<const Vec3> positions, std::span<const Triangle> triangles);

  /// New vertex positions for the same triangles (throws trocar::Error on a count mismatch).
  void refit(std::span<const Vec3> positions);

  /// Signed distance from p, using the tree. `hint`, when a valid triangle id (e.g. the
  /// triangle of the previous query from a nearby point), seeds the search bound with p's
  /// distance to it, so fewer nodes are visited; the result's distance is the same.
  SignedDistanceResult signed_distance(const Vec3& p, std::uint32_t hint = kNoTriangle) const;
  /// Work space of signed_distances(): the candidate triangles of a batch and their boxes, one
  /// array per coordinate so that the per-point box test runs as a vector loop. Sized once.
  class BatchScratch {
   public:
    /// Room for a batch on a mesh of up to `triangles` triangles.
    explicit BatchScratch(std::size_t triangles = 0);

   private:
    friend class MeshDistance;
    std::vector<std::uint32_t> ids_;
    std::vector<Real> box_[6];  // min x, y, z, max x, y, z of each candidate
    std::vector<Real> gap_;     // squared distance from the current point to each box
  };

  /// Signed distances of a batch of nearby points (e.g. an instrument's vertices near this mesh):
  /// results[k] is what signed_distance(points[k], hints[k]) gives, and hints[k] becomes its
  /// triangle. Instead of one tree walk per point, each point's distance to its hint triangle
  /// bounds its search; one walk collects every triangle whose box is nearer than the largest
  /// bound to the batch's box (no other triangle can be nearest to any of the points), and each
  /// point scans only those. Points without a hint get a tree query first. The three spans have
  /// one entry per point and `scratch` room for triangles().size() (throws trocar::Error
  /// otherwise). No allocation.
  void signed_distances(std::span<const Vec3> points, std::span<std::uint32_t> hints,
                        std::span<SignedDistanceResult> results, BatchScratch& scratch) const;
  /// Same as signed_distance() by testing every triangle (a reference for tests; O(n)).
  SignedDistanceResult signed_distance_brute_force(const Vec3& p) const;

  std::span<const Vec3> positions() const { return positions_; }      ///< current vertices
  std::span<const Triangle> triangles() const { return triangles_; }  ///< the triangles
  /// Unit normal of triangle t (zero for a degenerate triangle), from the current positions.
  Vec3 face_normal(std::uint32_t t) const;
  /// Unit angle-weighted pseudonormal of vertex v (zero for an unused vertex).
  Vec3 vertex_pseudonormal(std::uint32_t v) const;
  /// Unit pseudonormal of edge k (vertex k → k+1) of triangle t.
  Vec3 edge_pseudonormal(std::uint32_t t, int k) const;
  /// Number of distinct edges found (a closed manifold mesh has 3/2 per triangle).
  std::size_t edge_count() const { return edge_first_.empty() ? 0 : edge_first_.size() - 1; }
  /// The triangle tree.
  const AabbTree& tree() const { return tree_; }

 private:
  void update_boxes();
  /// Angle of triangle t at its corner k (radians) times the triangle's unit normal n.
  Vec3 weighted_corner_normal(std::uint32_t t, std::size_t k, const Vec3& n) const;
  SignedDistanceResult finish(const Vec3& p, std::uint32_t t, const TriangleClosestPoint& c,
                              Real d2) const;
  /// Offers triangle t as p's nearest: when its plane is no nearer than best_sq nothing changes,
  /// else its closest point replaces best (best_sq, best_t, best_c) if nearer.
  void offer(const Vec3& p, std::uint32_t t, Real& best_sq, std::uint32_t& best_t, TriangleClosestPoint& best_c) const;
  /// p's nearest triangle among the first `count` candidates in scratch, starting from seed
  /// (whose distance field holds the squared distance).
  SignedDistanceResult nearest_among(const Vec3& p, const SignedDistanceResult& seed,
                                     std::size_t count, BatchScratch& scratch) const;

  std::vector<Vec3> positions_;
  std::vector<Triangle> triangles_;
  std::vector<std::uint32_t> edge_of_slot_;  // 3t + k → edge id
  // Slots (3t + k) of edge e: edge_slots_[edge_first_[e] .. edge_first_[e + 1]), ascending.
  std::vector<std::uint32_t> edge_first_;
  std::vector<std::uint32_t> edge_slots_;
  // Corners (3t + k) at vertex v: vertex_corners_[vertex_first_[v] .. vertex_first_[v + 1]),
  // ascending.
  std::vector<std::uint32_t> vertex_first_;
  std::vector<std::uint32_t> vertex_corners_;
  std::vector<Aabb> boxes_;
  AabbTree tree_;
};

}  // namespace trocar
