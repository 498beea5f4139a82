#pragma once
/// Closest points on segments and triangles, with the feature (face, edge, vertex) they lie on.
#include <cstdint>

#include "trocar/core/types.h"

namespace trocar {

/// The part of a triangle a closest point lies on; selects the pseudonormal in signed distance.
enum class TriangleFeature : std::uint8_t {
  kFace,    ///< the open interior of the triangle
  kEdge,    ///< edge k, from vertex k to vertex (k + 1) mod 3, excluding its end vertices
  kVertex,  ///< vertex k
};

/// The closest point on a triangle to a query point.
struct TriangleClosestPoint {
  Vec3 point = Vec3::Zero();        ///< the closest point (the input's unit)
  Vec3 barycentric = Vec3::Zero();  ///< its barycentric coordinates, each in [0, 1], sum 1
  TriangleFeature feature = TriangleFeature::kFace;  ///< where on the triangle it lies
  int index = 0;  ///< vertex k or edge k (vertex k → vertex k+1); 0 for kFace
};

/// Parameter t ∈ [0, 1] of the point a + t·(b − a) of segment ab closest to p (dimensionless);
/// 0 when a = b.
Real closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);

/// The point of triangle abc closest to p. Regions as in Ericson, Real-Time Collision Detection
/// §5.1.5 (face, three edges, three vertices); the face test and the face point are computed in
/// an orthonormal frame on the longest edge, so the error stays ~ε·(triangle size) even for thin
/// slivers (the book's formulas lose a factor length/height there). Vertex order: a = 0, b = 1,
/// c = 2; edge 0 = ab, edge 1 = bc, edge 2 = ca. Degenerate triangles (twice the area ≤
/// kDegenerateRatio · longest edge²: collinear or repeated vertices) are treated as their three
/// edges, never dividing by zero; a point on a zero-length edge is reported as a vertex.
TriangleClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                               const Vec3& c);

/// Closest points between segments p0p1 and q0q1 (Ericson §5.1.9, with both degenerate cases:
/// zero-length segments are points). Parallel segments give one of the closest pairs.
struct SegmentSegmentClosest {
  Real s = 0;                 ///< parameter on p0p1 (dimensionless, [0, 1])
  Real t = 0;                 ///< parameter on q0q1 (dimensionless, [0, 1])
  Vec3 on_p = Vec3::Zero();   ///< p0 + s·(p1 − p0)
  Vec3 on_q = Vec3::Zero();   ///< q0 + t·(q1 − q0)
  Real distance_squared = 0;  ///< |on_p − on_q|² (the input's unit squared)
};
/// See SegmentSegmentClosest.
SegmentSegmentClosest closest_points_segment_segment(const Vec3& p0, const Vec3& p1,
                                                     const Vec3& q0, const Vec3& q1);

}  // namespace trocar
