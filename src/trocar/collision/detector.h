#pragma once
/// The collision detector of one simulation: a broad phase, the narrow phase and their buffers.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/collision_object.h"
#include "trocar/collision/contact.h"
#include "trocar/collision/ohc_broad_phase.h"

namespace trocar {

/// Wall-clock time of the last detect() (microseconds).
struct DetectorTimings {
  double broad_phase_us = 0;   ///< candidate pairs
  double narrow_phase_us = 0;  ///< exact tests and sort
  std::uint64_t candidate_pairs = 0;  ///< pairs the broad phase returned
  std::uint64_t contacts = 0;         ///< contacts found
};

/// Owns a broad phase, the candidate and contact buffers, and runs both phases. After a first
/// detect() with the same object sizes (and no more contacts than before), detect() allocates
/// nothing. Deterministic: the same input gives the same contacts in the same order.
class CollisionDetector {
 public:
  /// An OHC detector with default settings.
  CollisionDetector();
  /// A detector with a broad phase of the given kind (default settings).
  explicit CollisionDetector(BroadPhaseKind kind);
  /// An OHC detector with the given settings.
  explicit CollisionDetector(const OhcSettings& settings);
  /// A detector with the given broad phase (must not be null).
  explicit CollisionDetector(std::unique_ptr<BroadPhase> broad_phase);

  /// Finds every intersecting triangle pair between the objects; returns the contacts, sorted
  /// (valid until the next call).
  std::span<const Contact> detect(std::span<const CollisionObject> objects);
  /// Same, copying the contacts into `out` (reusing its capacity).
  void detect(std::span<const CollisionObject> objects, std::vector<Contact>& out);

  BroadPhase& broad_phase() { return *broad_phase_; }              ///< the broad phase
  const BroadPhase& broad_phase() const { return *broad_phase_; }  ///< the broad phase
  /// The OHC broad phase's statistics of the last frame, or null for another broad phase.
  const OhcStats* ohc_stats() const;
  /// The broad phase's candidate pairs of the last frame.
  std::span<const CandidatePair> candidates() const { return candidates_; }
  /// Only pairs with an instrument (BroadPhase::set_instrument_pairs_only).
  void set_instrument_pairs_only(bool on) { broad_phase_->set_instrument_pairs_only(on); }
  /// The last frame's contacts.
  std::span<const Contact> contacts() const { return contacts_; }
  /// Timings and counts of the last frame.
  const DetectorTimings& timings() const { return timings_; }

 private:
  std::unique_ptr<BroadPhase> broad_phase_;
  std::vector<CandidatePair> candidates_;
  std::vector<Contact> contacts_;
  DetectorTimings timings_;
};

}  // namespace trocar
