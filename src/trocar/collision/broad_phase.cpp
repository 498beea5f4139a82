#include "trocar/collision/broad_phase.h"

#include <algorithm>

#include "trocar/collision/brute_force_broad_phase.h"
#include "trocar/collision/bvh_broad_phase.h"
#include "trocar/collision/ohc_broad_phase.h"

namespace trocar {

const char* broad_phase_name(BroadPhaseKind kind) {
  switch (kind) {
    case BroadPhaseKind::kOhc: return "ohc";
    case BroadPhaseKind::kBvh: return "bvh";
    case BroadPhaseKind::kBruteForce: return "brute";
  }
  return "unknown";
}

std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseKind kind) {
  switch (kind) {
    case BroadPhaseKind::kOhc: return std::make_unique<OhcBroadPhase>();
    case BroadPhaseKind::kBvh: return std::make_unique<BvhBroadPhase>();
    case BroadPhaseKind::kBruteForce: return std::make_unique<BruteForceBroadPhase>();
  }
  return std::make_unique<OhcBroadPhase>();
}

Aabb object_box(const CollisionObject& object) {
  Aabb box;
  if (object.triangles.empty() || object.positions.empty()) return box;
  // Scalar min/max over flat doubles (vectorises; Eigen's cwiseMin on Vec3 does not).
  Real lo[3] = {box.min.x(), box.min.y(), box.min.z()};
  Real hi[3] = {box.max.x(), box.max.y(), box.max.z()};
  for (const Vec3& p : object.positions) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  box.min = Vec3(lo[0], lo[1], lo[2]);
  box.max = Vec3(hi[0], hi[1], hi[2]);
  return box.inflated(kBoxMargin * box.size().maxCoeff());
}

}  // namespace trocar
