#include "trocar/geometry/segment_plane.h"

#include <gtest/gtest.h>

namespace trocar {
namespace {

TEST(SegmentPlane, CrossingGivesParameterAndPoint) {
  // z from −1 to 3 crosses z = 0 a quarter of the way: t = 1/4, point (0.5, 0.25, 0) for a
  // segment from (0,0,−1) to (2,1,3).
  const SegmentPlaneHit h = intersect_segment_plane(Vec3(0, 0, -1), Vec3(2, 1, 3), Vec3(7, 7, 0),
                                                    Vec3(0, 0, 5));  // non-unit normal
  ASSERT_EQ(h.kind, SegmentPlaneKind::kPoint);
  EXPECT_NEAR(h.t, 0.25, 1e-15);
  EXPECT_NEAR((h.point - Vec3(0.5, 0.25, 0)).norm(), 0.0, 1e-15);
}

TEST(SegmentPlane, TiltedPlane) {
  // Plane x + y + z = 3 (normal (1,1,1) through (1,1,1)); segment from 0 to (3,3,3):
  // d = (x+y+z−3)/√3 gives d_a = −√3, d_b = 2√3 → t = 1/3, point (1,1,1).
  const SegmentPlaneHit h = intersect_segment_plane(Vec3(0, 0, 0), Vec3(3, 3, 3), Vec3(1, 1, 1),
                                                    Vec3(1, 1, 1));
  ASSERT_EQ(h.kind, SegmentPlaneKind::kPoint);
  EXPECT_NEAR(h.t, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR((h.point - Vec3(1, 1, 1)).norm(), 0.0, 1e-14);
}

TEST(SegmentPlane, MissesEndsOnPlaneAndInPlane) {
  const Vec3 o(0, 0, 0), n(0, 0, 1);
  EXPECT_EQ(intersect_segment_plane(Vec3(0, 0, 1), Vec3(1, 0, 2), o, n).kind,
            SegmentPlaneKind::kNone);
  const SegmentPlaneHit end = intersect_segment_plane(Vec3(0, 0, 1), Vec3(1, 2, 0), o, n);
  ASSERT_EQ(end.kind, SegmentPlaneKind::kPoint);
  EXPECT_EQ(end.t, 1.0);
  EXPECT_EQ(end.point, Vec3(1, 2, 0));
  const SegmentPlaneHit in = intersect_segment_plane(Vec3(0, 0, 0), Vec3(1, 2, 0), o, n);
  EXPECT_EQ(in.kind, SegmentPlaneKind::kInPlane);
  EXPECT_EQ(in.point, Vec3(0, 0, 0));
  // Within the tolerance (1e-9 here) counts as in the plane.
  EXPECT_EQ(intersect_segment_plane(Vec3(0, 0, 1e-10), Vec3(1, 2, -1e-10), o, n, 1e-9).kind,
            SegmentPlaneKind::kInPlane);
  EXPECT_EQ(intersect_segment_plane(Vec3(0, 0, 1), Vec3(0, 0, -1), o, Vec3::Zero()).kind,
            SegmentPlaneKind::kNone);
}

}  // namespace
}  // namespace trocar
