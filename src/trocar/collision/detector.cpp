#include "trocar/collision/detector.h"

#include "trocar/collision/narrow_phase.h"
#include "trocar/core/error.h"
#include "trocar/core/timer.h"

namespace trocar {

CollisionDetector::CollisionDetector() : CollisionDetector(BroadPhaseKind::kOhc) {}

CollisionDetector::CollisionDetector(BroadPhaseKind kind) : broad_phase_(make_broad_phase(kind)) {}

CollisionDetector::CollisionDetector(const OhcSettings& settings)
    : broad_phase_(std::make_unique<OhcBroadPhase>(settings)) {}

CollisionDetector::CollisionDetector(std::unique_ptr<BroadPhase> broad_phase)
    : broad_phase_(std::move(broad_phase)) {
  if (!broad_phase_) throw Error("CollisionDetector: null broad phase");
}

std::span<const Contact> CollisionDetector::detect(std::span<const CollisionObject> objects) {
  Timer timer;
  broad_phase_->find_pairs(objects, candidates_);
  timings_.broad_phase_us = timer.microseconds();
  timer.restart();
  narrow_phase(objects, candidates_, contacts_);
  timings_.narrow_phase_us = timer.microseconds();
  timings_.candidate_pairs = candidates_.size();
  timings_.contacts = contacts_.size();
  return contacts_;
}

void CollisionDetector::detect(std::span<const CollisionObject> objects, std::vector<Contact>& out) {
  const std::span<const Contact> found = detect(objects);
  out.assign(found.begin(), found.end());
}

const OhcStats* CollisionDetector::ohc_stats() const {
  const auto* ohc = dynamic_cast<const OhcBroadPhase*>(broad_phase_.get());
  return ohc ? &ohc->stats() : nullptr;
}

}  // namespace trocar
