// segment_crosses_triangle by hand: a segment through the middle, beside the triangle, short of
// it, parallel to it, and one ending on the face.
#include <gtest/gtest.h>

#include "trocar/geometry/segment_triangle.h"

namespace trocar {
namespace {

const Vec3 kA(0, 0, 0), kB(1, 0, 0), kC(0, 1, 0);  // the unit right triangle in z = 0

TEST(SegmentTriangle, ThroughTheFaceCrossesEitherWay) {
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.25, 0.25, -1), Vec3(0.25, 0.25, 1), kA, kB, kC));
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.25, 0.25, 1), Vec3(0.25, 0.25, -1), kA, kB, kC));
  // Slanted, through (0.4, 0.1, 0): the segment from (0.2, 0.3, −1) to (0.6, −0.1, 1).
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.2, 0.3, -1), Vec3(0.6, -0.1, 1), kA, kB, kC));
}

TEST(SegmentTriangle, BesideShortOfOrAlongTheFaceDoesNot) {
  EXPECT_FALSE(segment_crosses_triangle(Vec3(0.6, 0.6, -1), Vec3(0.6, 0.6, 1), kA, kB, kC));  // past the hypotenuse
  EXPECT_FALSE(segment_crosses_triangle(Vec3(0.25, 0.25, 0.1), Vec3(0.25, 0.25, 1), kA, kB, kC));  // short of it
  EXPECT_FALSE(segment_crosses_triangle(Vec3(-1, 0.2, 0), Vec3(2, 0.2, 0), kA, kB, kC));  // in its plane
  EXPECT_FALSE(segment_crosses_triangle(Vec3(0.25, 0.25, -1), Vec3(0.25, 0.25, 1), kA, kA, kC));  // degenerate
}

TEST(SegmentTriangle, AnEndOnTheFaceCounts) {
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.25, 0.25, 0), Vec3(0.25, 0.25, 1), kA, kB, kC));
}

}  // namespace
}  // namespace trocar
