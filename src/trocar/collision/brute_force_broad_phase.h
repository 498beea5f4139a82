#pragma once
/// Brute-force broad phase: every triangle pair of every overlapping object pair (reference).
#include <span>
#include <vector>

#include "trocar/collision/broad_phase.h"

namespace trocar {

/// Returns every triangle pair (no box test) of every tested object pair whose object boxes
/// overlap. O(n·m): the reference the other broad phases are checked against.
class BruteForceBroadPhase final : public BroadPhase {
 public:
  void find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) override;
  BroadPhaseKind kind() const override { return BroadPhaseKind::kBruteForce; }
};

}  // namespace trocar
