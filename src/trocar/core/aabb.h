#pragma once
/// Axis-aligned bounding box.
#include <limits>
#include <span>

#include "trocar/core/types.h"

namespace trocar {

/// An axis-aligned box [min, max]. The default box is empty (min > max) and grows with expand().
struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<Real>::infinity());   ///< lower corner
  Vec3 max = Vec3::Constant(-std::numeric_limits<Real>::infinity());  ///< upper corner

  /// The smallest box holding every point (empty for no points).
  static Aabb of_points(std::span<const Vec3> points);

  /// True when no point has been added.
  bool is_empty() const { return (min.array() > max.array()).any(); }
  /// Grows the box to hold p.
  void expand(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  /// Grows the box to hold b.
  void expand(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  /// Grows the box by margin on every side.
  Aabb inflated(Real margin) const {
    return {(min.array() - margin).matrix(), (max.array() + margin).matrix()};
  }
  /// True when the closed boxes share at least one point.
  bool overlaps(const Aabb& b) const {
    return (min.array() <= b.max.array()).all() && (b.min.array() <= max.array()).all();
  }
  /// True when p lies in the closed box.
  bool contains(const Vec3& p) const {
    return (min.array() <= p.array()).all() && (p.array() <= max.array()).all();
  }
  /// The overlap of two boxes (empty when they do not overlap).
  Aabb intersection(const Aabb& b) const { return {min.cwiseMax(b.min), max.cwiseMin(b.max)}; }
  Vec3 center() const { return 0.5 * (min + max); }   ///< midpoint
  Vec3 size() const { return max - min; }             ///< edge lengths
  Real diagonal() const { return is_empty() ? 0.0 : size().norm(); }  ///< length of the diagonal
};

}  // namespace trocar
