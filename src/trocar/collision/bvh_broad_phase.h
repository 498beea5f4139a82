#pragma once
/// BVH broad phase: one AABB tree per object, refitted every frame, traversed tree against tree.
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/geometry/aabb_tree.h"

namespace trocar {

/// Per-object AabbTree (geometry/aabb_tree.h) over the inflated triangle boxes. A tree is built
/// the first time an object is seen (allocates) and only refitted afterwards (topology fixed,
/// boxes recomputed bottom-up: the usual choice for deforming meshes); it is rebuilt when the
/// object's identity changes (see CollisionObject). Pairs of overlapping objects are traversed
/// simultaneously with an explicit stack (descend into the larger node), leaf pairs test their
/// item boxes. After warm-up no allocation.
class BvhBroadPhase final : public BroadPhase {
 public:
  void find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) override;
  BroadPhaseKind kind() const override { return BroadPhaseKind::kBvh; }

  /// Node-pair tests in the last frame (box overlap tests between tree nodes).
  std::uint64_t node_tests() const { return node_tests_; }

 private:
  /// One object's cached tree and triangle boxes.
  struct ObjectTree {
    const Triangle* triangles = nullptr;  ///< identity: triangle span data
    std::size_t triangle_count = 0;       ///< identity: triangle span size
    std::size_t vertex_count = 0;         ///< identity: vertex count
    std::vector<Aabb> boxes;              ///< inflated triangle boxes of this frame
    AabbTree tree;                        ///< topology from the first frame, refitted
    bool refitted = false;                ///< refitted this frame
  };
  struct NodePair {
    std::uint32_t a, b;
  };

  void refit(ObjectTree& t, const CollisionObject& object);

  std::vector<ObjectTree> trees_;
  std::vector<NodePair> stack_;
  std::uint64_t node_tests_ = 0;
};

}  // namespace trocar
