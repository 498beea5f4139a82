#pragma once
/// Barycentric (areal) coordinates of a point with respect to a triangle.
#include "trocar/core/types.h"

namespace trocar {

/// Barycentric coordinates (u, v, w) of p with respect to triangle abc: u·a + v·b + w·c is the
/// orthogonal projection of p onto the triangle's plane, and u + v + w = 1 (dimensionless).
/// Inside the triangle all three are in [0, 1]; outside, some are negative (no clamping).
///
/// Degenerate triangle (twice the area ≤ kDegenerateRatio · longest edge², tolerance.h): the
/// triangle is treated as its longest edge ij; the result is (1 − t) at i, t at j and 0 at the
/// third vertex, with t the unclamped parameter of p's projection on the line ij. When all three
/// vertices coincide the result is (1, 0, 0). Never NaN for finite input.
Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace trocar
