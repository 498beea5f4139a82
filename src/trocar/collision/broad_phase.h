#pragma once
/// The broad-phase interface: candidate triangle pairs for the exact narrow phase.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/contact.h"
#include "trocar/core/aabb.h"

namespace trocar {

/// A pair of triangles that may intersect, in contact order (object_first(object_a, object_b)).
struct CandidatePair {
  std::uint32_t object_a = 0;    ///< first object in contact order
  std::uint32_t object_b = 0;    ///< second object
  std::uint32_t triangle_a = 0;  ///< triangle of object_a
  std::uint32_t triangle_b = 0;  ///< triangle of object_b
};

/// The broad phases trocar has.
enum class BroadPhaseKind : std::uint8_t {
  kOhc,         ///< cascaded spatial hash (OhcBroadPhase), the simulator's default
  kBvh,         ///< per-object AABB trees, refitted each frame, tree-vs-tree (BvhBroadPhase)
  kBruteForce,  ///< every triangle pair of every overlapping object pair (reference)
};

/// Lower-case name ("ohc", "bvh", "brute").
const char* broad_phase_name(BroadPhaseKind kind);

/// Relative inflation of every triangle and object box: a box of largest side s grows by
/// kBoxMargin·s on every side. The narrow phase counts pairs closer than 1e-12 of their size as
/// touching (kTriTriTolerance), so un-inflated boxes could reject a pair it accepts; the margin
/// (1000× that tolerance) makes every broad phase return every pair the brute force finds.
/// Dimensionless.
inline constexpr Real kBoxMargin = 1e-9;

/// Finds the triangle pairs that may intersect. Every pair the narrow phase would report as
/// intersecting is returned, each at most once; pairs of one object with itself and rigid–rigid
/// pairs are never returned. Implementations keep their buffers between calls: after a first
/// call with the same sizes, find_pairs() allocates nothing.
class BroadPhase {
 public:
  virtual ~BroadPhase() = default;
  /// Replaces `out` with the candidate pairs of `objects` (any order; the narrow phase sorts).
  virtual void find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) = 0;
  /// Which broad phase this is.
  virtual BroadPhaseKind kind() const = 0;
  /// Object `object`'s triangles are about to be replaced by a topology change (a cut): new
  /// triangle k was old triangle triangle_origin[k] (one-to-one). A broad phase that keeps
  /// per-object structure may reuse it for the new triangles; the result of find_pairs() must
  /// stay the same set of pairs. Default: nothing (the next find_pairs rebuilds what changed).
  virtual void remap_object(std::size_t object, std::span<const std::uint32_t> triangle_origin) {
    (void)object;
    (void)triangle_origin;
  }
  /// With true, only pairs with an instrument are returned (the simulator's step: tissue against
  /// tissue is answered by the tissue contact solver, response/tissue_contact.h, from its own
  /// proximity search, so the detector need not find those pairs at all).
  void set_instrument_pairs_only(bool on) { instrument_pairs_only_ = on; }
  bool instrument_pairs_only() const { return instrument_pairs_only_; }

 protected:
  /// Whether objects of these roles are tested against each other.
  bool tested(ObjectRole a, ObjectRole b) const {
    return roles_tested(a, b) && (!instrument_pairs_only_ || a == ObjectRole::kInstrument || b == ObjectRole::kInstrument);
  }

 private:
  bool instrument_pairs_only_ = false;
};

/// A new broad phase of the given kind with default settings.
std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseKind kind);

/// Box of an object's positions, inflated by kBoxMargin of its largest side (empty when the
/// object has no triangles).
Aabb object_box(const CollisionObject& object);

/// Box of one triangle, inflated by kBoxMargin of its largest side. Inline: the OHC and BVH
/// call it for every triangle they open, every frame.
inline Aabb triangle_box(const Vec3& a, const Vec3& b, const Vec3& c) {
  Aabb box;
  box.min = a.cwiseMin(b).cwiseMin(c);
  box.max = a.cwiseMax(b).cwiseMax(c);
  return box.inflated(kBoxMargin * box.size().maxCoeff());
}

}  // namespace trocar
