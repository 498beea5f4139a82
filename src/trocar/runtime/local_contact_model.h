#pragma once
/// The local contact model that physics hands to the haptic thread after each step (the
/// intermediate representation of Adachi et al. 1995 and Mark et al. 1996; multirate scheme of
/// Çavuşoğlu & Tendick 2000): the contact force at the pose physics used, and how it changes
/// with the instrument's position, so that the haptic tick renders a force that follows the
/// device between physics updates.
#include <array>
#include <cstdint>

#include "trocar/core/types.h"

namespace trocar {

/// Instruments the runtime drives at once (the seed's two PHANTOMs, with room to spare).
inline constexpr std::size_t kMaxRuntimeInstruments = 4;

/// One instrument's model, linearised at position0:
///   F(x) = force0 + k n nᵀ (position0 − x)   while n·F(x) > 0, else 0 (the tissue never pulls).
/// The Jacobian is −k n nᵀ: stiff along the contact normal n, free across it (the tangential part
/// of force0, friction, is held). k is the effective stiffness at the contact: the penalty
/// stiffness in series with the tissue's compliance (for the sdf constraint the penalty is
/// infinite, so it is the tissue's own), estimated by ContactStiffnessEstimator.
struct LocalContactModel {
  Vec3 position0 = Vec3::Zero();  ///< instrument (proxy) position physics stepped at (m, world)
  Vec3 force0 = Vec3::Zero();     ///< force on the instrument there (N, world; clamped by max_force)
  Vec3 normal = Vec3::Zero();     ///< unit contact normal, the direction of force0 (0 when free)
  Real stiffness = 0;             ///< effective stiffness along the normal (N/m)
  bool in_contact = false;        ///< force0 is non-zero

  /// The force at position x (N).
  Vec3 force_at(const Vec3& x) const;
};

/// What physics publishes after each step: one model per instrument.
struct ContactModelSet {
  std::array<LocalContactModel, kMaxRuntimeInstruments> instruments{};  ///< by instrument index
  std::uint64_t step = 0;          ///< physics steps done (0 = none yet)
  std::int64_t timestamp_ns = 0;   ///< steady-clock time the step ended (ns)
};

/// Estimates k along the normal from consecutive steps (a secant of the force–position curve,
/// smoothed), starting from a prior. A secant is taken only when the instrument moved along the
/// normal by more than kMinMove (else the force change is the tissue's own dynamics, not
/// stiffness). Allocation-free.
class ContactStiffnessEstimator {
 public:
  /// prior: k used until a secant is measured (N/m); max: upper clamp (N/m).
  ContactStiffnessEstimator(Real prior = 500, Real max = 1e5) : prior_(prior), max_(max) {}
  /// Feeds the step's position (m) and force (N) and returns the model at that position.
  LocalContactModel update(const Vec3& position, const Vec3& force);
  /// Forgets the contact (the next contact starts from the prior).
  void reset();

  static constexpr Real kMinMove = 20e-6;   ///< m along the normal for a secant
  static constexpr Real kSmoothing = 0.3;   ///< weight of a new secant in the running estimate

 private:
  Real prior_;
  Real max_;
  Real k_ = 0;           ///< current estimate (0 = none yet)
  bool have_last_ = false;
  Vec3 last_position_ = Vec3::Zero();
  Vec3 last_force_ = Vec3::Zero();
};

}  // namespace trocar
