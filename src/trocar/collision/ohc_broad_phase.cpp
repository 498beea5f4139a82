#include "trocar/collision/ohc_broad_phase.h"

namespace trocar {

// Stub: replaced by the cascaded hash.
void OhcBroadPhase::find_pairs(std::span<const CollisionObject>, std::vector<CandidatePair>& out) {
  out.clear();
  stats_ = {};
}

void OhcBroadPhase::emit_cell_pairs(std::span<const Entry>, std::span<const CollisionObject>,
                                    std::vector<CandidatePair>&) {}

}  // namespace trocar
