#pragma once
/// A named region of the anatomy that a trainee must not injure (the "triangle of doom", the
/// vessels): a flat polygon with a depth, i.e. a prism about the polygon's plane. A point is in
/// the zone when its projection onto the plane falls inside the polygon and it lies within
/// `depth` of the plane on either side. Plain data plus the test.
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// One named zone (scene key "zones", or generated with the anatomy).
struct NamedZone {
  std::string name;            ///< e.g. "triangle_of_doom"
  std::vector<Vec3> polygon;   ///< ≥ 3 coplanar corners (m), in order around the polygon
  Real depth = 0.005;          ///< half-thickness of the prism (m)

  /// The polygon's unit normal (Newell's method; zero for a degenerate polygon).
  Vec3 normal() const;
  /// True when `p` (m) is inside the prism.
  bool contains(const Vec3& p) const;
};

/// The first zone of `zones` that contains p, or nullptr.
const NamedZone* zone_containing(const std::vector<NamedZone>& zones, const Vec3& p);

}  // namespace trocar
