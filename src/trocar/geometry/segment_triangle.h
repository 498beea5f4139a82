#pragma once
/// Whether a line segment passes through a triangle.
#include "trocar/core/types.h"

namespace trocar {

/// True when segment pq meets triangle abc at a point of both, by the Möller–Trumbore test
/// (Möller & Trumbore 1997, "Fast, minimum storage ray/triangle intersection") restricted to the
/// segment: barycentric u, v ≥ 0, u + v ≤ 1 and the segment's parameter in [0, 1]. A segment in
/// the triangle's plane (or a degenerate triangle) counts as not crossing.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace trocar
