#pragma once
/// Exact-predicate triangle–triangle intersection test returning the intersection segment.
#include "trocar/core/types.h"

namespace trocar {

/// Result of intersect_triangles. Points are in the input's unit.
struct TriTriResult {
  bool intersects = false;  ///< the closed triangles share at least one point (touching counts)
  /// The pair was handled in one plane: both triangles lie in a common plane within the
  /// tolerance (or, for a degenerate input, the segment lies in the other triangle's plane, or
  /// both inputs are degenerate and intersect). May be true when !intersects.
  bool coplanar = false;
  /// Intersection segment PQ (P = Q for a single touching point); zero when !intersects.
  /// Non-coplanar: the exact intersection segment of the two triangles, ordered along the
  /// intersection line. Coplanar: the longest chord of the overlap polygon (its two vertices
  /// farthest apart), a representative segment of a 2-D overlap.
  Vec3 p = Vec3::Zero();
  Vec3 q = Vec3::Zero();  ///< the other end of the segment (see p)
};

/// Intersection of closed triangles A = (a0, a1, a2) and B = (b0, b1, b2).
///
/// Method: Möller's interval-overlap test ("A Fast Triangle-Triangle Intersection Test", JGT
/// 1997): signed distances of each triangle's vertices to the other's plane reject separated
/// pairs; otherwise each triangle's trace on the other's plane is a segment on the common line,
/// and the answer is the overlap of the two segments. Unlike the paper, the traces are kept as
/// 3-D points (interpolated along the crossing edges), so the segment ends are computed exactly
/// where an edge pierces a plane; the 1-D parameter used to order them is the projection on
/// nA × nB, or on the longer trace when the planes are nearly parallel (whichever is better
/// conditioned).
///
/// Tolerance (tolerance.h): with L the pair's size, distances |d| ≤ kTriTriTolerance·L count
/// as 0, so touching at a vertex or an edge is an intersection (P = Q for a point).
///
/// Coplanar (every vertex of one triangle within the tolerance of the other's plane): that
/// triangle is clipped against the three edge half-planes of the other (Sutherland–Hodgman).
/// They intersect iff the clip with half-planes widened by the tolerance is non-empty; PQ is the
/// diameter of the exact (unwidened) clip, or, when the triangles only touch, of the widened
/// one, whose corners lie within a few tolerances of both triangles.
///
/// Degenerate triangles (twice the area ≤ kDegenerateRatio · longest edge²): handled as their
/// longest edge (a point when all vertices coincide): segment–triangle (plane crossing plus
/// inside test, or in-plane clipping), segment–segment (closest points within the tolerance;
/// collinear overlapping segments return the overlap). Non-finite input returns !intersects.
/// No allocation; never NaN for finite input.
TriTriResult intersect_triangles(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                                 const Vec3& b1, const Vec3& b2);

}  // namespace trocar
