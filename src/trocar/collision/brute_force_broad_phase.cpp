#include "trocar/collision/brute_force_broad_phase.h"

namespace trocar {

void BruteForceBroadPhase::find_pairs(std::span<const CollisionObject> objects,
                                      std::vector<CandidatePair>& out) {
  out.clear();
  const auto n = static_cast<std::uint32_t>(objects.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      if (!tested(objects[i].role, objects[j].role)) continue;
      const Aabb bi = object_box(objects[i]);
      const Aabb bj = object_box(objects[j]);
      if (bi.is_empty() || bj.is_empty() || !bi.overlaps(bj)) continue;
      const bool i_first = object_first(objects[i].role, i, objects[j].role, j);
      const std::uint32_t a = i_first ? i : j;
      const std::uint32_t b = i_first ? j : i;
      const auto na = static_cast<std::uint32_t>(objects[a].triangles.size());
      const auto nb = static_cast<std::uint32_t>(objects[b].triangles.size());
      for (std::uint32_t ta = 0; ta < na; ++ta) {
        for (std::uint32_t tb = 0; tb < nb; ++tb) out.push_back({a, b, ta, tb});
      }
    }
  }
}

}  // namespace trocar
