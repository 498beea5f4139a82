#pragma once
/// Contact between deformable bodies and attachments between their surfaces: the prosthetic mesh
/// resting on the abdominal wall without crossing it or itself, and the tacks that fix it there
/// (docs/response.md, "Tissue against tissue"). Runs once per step after every tissue's integrator
/// and instrument response. No allocation after warm-up (attachments up to their capacity).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {

/// Two tissues whose surfaces must stay apart by `thickness` (scene key "tissue_contacts");
/// a == b is a tissue's contact with itself (a cloth that must not cross itself).
struct TissueContactPair {
  std::size_t a = 0;         ///< tissue index
  std::size_t b = 0;         ///< tissue index (== a: self contact)
  Real thickness = 1e-3;     ///< the gap kept between the surfaces (m)
  Real friction = 0.3;       ///< Coulomb coefficient of the tangential correction
};

/// A point on a tissue's surface, carried by the triangle it lies in.
struct SurfacePoint {
  std::uint32_t tissue = 0;    ///< tissue index
  std::uint32_t triangle = 0;  ///< triangle of the tissue's settings.triangles
  Vec3 bary = Vec3(1, 0, 0);   ///< barycentric weights (sum 1)
};

/// Two surface points held together (a tack through the mesh into the tissue): a zero-length
/// compliant constraint that lets go for good when its force exceeds `pullout_force`.
struct AttachmentSpec {
  SurfacePoint a;              ///< e.g. on the prosthetic mesh
  SurfacePoint b;              ///< e.g. on the abdominal wall
  Real pullout_force = 28.6;   ///< N; docs/response.md cites the figure
  Real compliance = 1e-4;      ///< m/N (the inverse of the tack's stiffness)
};

/// An attachment and what it did.
struct AttachmentState {
  AttachmentSpec spec;
  bool holding = true;   ///< false once torn out
  Real force = 0;        ///< the constraint force of the last step (N)
  Real torn_at = -1;     ///< simulated time it tore (s), < 0 while holding
};

/// The tissues as the solver sees them (pieces live in the World; they never move).
struct ContactTissue {
  const MassSpringSettings* settings = nullptr;
  MassSpringState* state = nullptr;
};

/// Solves the pairs' contacts and the attachments after the integrators.
class TissueContactSolver {
 public:
  /// `attachment_capacity`: attachments held without allocating.
  TissueContactSolver(std::vector<ContactTissue> tissues, std::vector<TissueContactPair> pairs,
                      std::size_t attachment_capacity = 256);
  ~TissueContactSolver();
  TissueContactSolver(const TissueContactSolver&) = delete;
  TissueContactSolver& operator=(const TissueContactSolver&) = delete;

  /// At the start of a step, before the integrators: remembers the positions the surfaces start
  /// from (which side of a surface each vertex is on).
  void begin_step();
  /// After the integrators: pushes the surfaces apart, holds the attachments (tearing those above
  /// their pull-out force at `time`), and corrects the velocities for the step dt.
  void solve(Real dt, Real time);

  /// Adds an attachment; returns its index, or SIZE_MAX when the capacity is full or the spec
  /// names a tissue or triangle that does not exist.
  std::size_t attach(const AttachmentSpec& spec);
  std::span<const AttachmentState> attachments() const { return attachments_; }
  std::span<const TissueContactPair> pairs() const { return pairs_; }
  /// Vertices the last solve moved (all pairs).
  std::uint32_t corrected() const { return corrected_; }

 private:
  std::vector<ContactTissue> tissues_;
  std::vector<TissueContactPair> pairs_;
  std::vector<AttachmentState> attachments_;
  std::size_t capacity_ = 0;
  std::uint32_t corrected_ = 0;
};

/// The world position of a surface point.
Vec3 surface_position(const MassSpringSettings& settings, const MassSpringState& state, const SurfacePoint& p);

}  // namespace trocar
