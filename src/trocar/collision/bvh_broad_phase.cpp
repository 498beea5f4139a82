#include "trocar/collision/bvh_broad_phase.h"

namespace trocar {

// Stub: replaced by the refitted trees.
void BvhBroadPhase::find_pairs(std::span<const CollisionObject>, std::vector<CandidatePair>& out) {
  out.clear();
  node_tests_ = 0;
}

void BvhBroadPhase::refit(ObjectTree&, const CollisionObject&) {}

}  // namespace trocar
