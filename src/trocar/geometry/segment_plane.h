#pragma once
/// Intersection of a line segment with a plane.
#include <cstdint>

#include "trocar/core/types.h"

namespace trocar {

/// How a segment meets a plane.
enum class SegmentPlaneKind : std::uint8_t {
  kNone,     ///< no common point (both ends strictly on one side, or a zero normal)
  kPoint,    ///< one common point (a crossing, or one end on the plane)
  kInPlane,  ///< both ends within the tolerance of the plane: the whole segment lies in it
};

/// Result of intersect_segment_plane.
struct SegmentPlaneHit {
  SegmentPlaneKind kind = SegmentPlaneKind::kNone;  ///< see SegmentPlaneKind
  Real t = 0;               ///< parameter of the point on a→b, in [0, 1] (0 for kInPlane/kNone)
  Vec3 point = Vec3::Zero();  ///< a + t·(b − a) (the input's unit); a for kInPlane
};

/// Where segment ab crosses the plane {x : n·(x − plane_point) = 0}. n need not be unit. Signed
/// distances of a and b to the plane (in the input's unit) whose magnitude is at most
/// `tolerance` count as zero (on the plane). With d_a, d_b of strictly opposite signs,
/// t = d_a / (d_a − d_b) (similar triangles). An end on the plane gives t = 0 or 1.
/// Never NaN for finite input.
SegmentPlaneHit intersect_segment_plane(const Vec3& a, const Vec3& b, const Vec3& plane_point,
                                        const Vec3& plane_normal, Real tolerance = 0);

}  // namespace trocar
