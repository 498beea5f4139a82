#pragma once
/// Oriented bounding box fitted by principal component analysis.
#include <array>
#include <span>

#include "trocar/core/aabb.h"
#include "trocar/core/types.h"

namespace trocar {

/// A box with centre, orthonormal right-handed axes (the columns of `axes`) and half-extents
/// along each axis. The seed (§3.6) fits it once when the instrument is loaded and moves it
/// with the instrument's pose.
struct Obb {
  Vec3 center = Vec3::Zero();        ///< centre of the box
  Mat3 axes = Mat3::Identity();      ///< column k is the unit axis a_k; det = +1
  Vec3 half_extents = Vec3::Zero();  ///< half the box's size along each axis (≥ 0)

  /// Fits a box to points: axes are the eigenvectors of the points' covariance (sorted by
  /// decreasing variance, so axis 0 is the longest direction), extents are the points'
  /// projections onto them, so every point is inside. Empty input gives a zero box at 0.
  static Obb fit_pca(std::span<const Vec3> points);

  /// True when p is inside the box, allowing `tolerance` (same unit) outside each face.
  bool contains(const Vec3& p, Real tolerance = 0) const;
  /// p in box coordinates: (a_0·(p−c), a_1·(p−c), a_2·(p−c)).
  Vec3 to_local(const Vec3& p) const { return axes.transpose() * (p - center); }
  /// The eight corners.
  std::array<Vec3, 8> corners() const;
  /// The smallest axis-aligned box holding this box.
  Aabb bounds() const;
  /// Volume of the box.
  Real volume() const { return 8.0 * half_extents.prod(); }
};

}  // namespace trocar
