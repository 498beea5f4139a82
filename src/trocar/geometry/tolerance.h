#pragma once
/// Tolerances shared by the geometry kernels (see docs/geometry.md).
#include "trocar/core/types.h"

namespace trocar {

/// A triangle is degenerate (treated as a segment or a point) when twice its area is at most
/// kDegenerateRatio · (longest edge)², i.e. its height is below 1e-12 of its longest edge.
/// Dimensionless.
inline constexpr Real kDegenerateRatio = 1e-12;

/// Relative tolerance of the triangle–triangle test: signed distances and in-plane edge tests
/// whose magnitude is at most kTriTriTolerance · L count as zero ("touching"), where L is the
/// largest side of the bounding box of the six vertices (the pair's size, independent of where
/// the pair is and of the argument order). Dimensionless; ≈ 4500 ulp, far above the rounding error
/// of the plane distances (a few ulp of L) and far below any geometric feature of interest.
inline constexpr Real kTriTriTolerance = 1e-12;

}  // namespace trocar
