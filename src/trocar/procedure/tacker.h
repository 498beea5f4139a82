#pragma once
/// The tacker: firing drives a tack at the instrument's tip. Where the prosthetic mesh and a tissue
/// both lie within reach of the tip, the mesh is fixed to the tissue there (Simulation::attach);
/// a tack into tissue alone, into the mesh alone, into nothing or into a named zone is recorded as
/// such (docs/procedure.md, "The tacker"). Firing happens a few times per procedure, so a linear
/// scan over the tissues' triangles is fine; it allocates nothing but the record's strings.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>

#include "trocar/core/types.h"
#include "trocar/geometry/zone.h"
#include "trocar/instrument/instrument.h"
#include "trocar/response/tissue_contact.h"
#include "trocar/sim/simulation.h"

namespace trocar {

inline constexpr std::size_t kNoIndex = std::numeric_limits<std::size_t>::max();

/// How a tacker fires.
struct TackerRules {
  std::size_t mesh_tissue = kNoIndex;  ///< the prosthetic mesh's tissue index (kNoIndex: no mesh)
  /// The tack takes hold where a surface lies within this distance of the tip's face (m).
  Real reach = 0.002;
  /// The tip's face, a disc about the tip point across the firing axis (m): a 5 mm tacker less
  /// its 1 mm bevel (make_tacker). The reach counts from the face, not its centre: a shaft that
  /// comes in 55–65° off the wall's normal (the groin from the ports) touches with the rim of
  /// its face first, so a reach from the centre would ask the rim to press the mesh through its
  /// contact gap into the wall. 0: a point.
  Real tip_radius = 0.0015;
  /// Pull-out force of the attachment (N): a titanium spiral tack, 28.6 ± 4.9 N (single-device
  /// pull-off, porcine rectus; Byrd et al. 2011, Hernia 15:553).
  Real pullout_force = 28.6;
  Real compliance = 1e-4;  ///< m/N, the tack's inverse stiffness (AttachmentSpec::compliance)
  /// The tip in the instrument's local frame (m) and the firing axis (local, out of the tip);
  /// unset: the end of the local box's long axis away from the top vertex (see tacker_tip()).
  std::optional<Vec3> tip_local;
  std::optional<Vec3> axis_local;
};

/// What one tack did.
enum class TackOutcome : std::uint8_t {
  kFixed,       ///< through the mesh into a tissue: an attachment holds them together
  kTissueOnly,  ///< into a tissue with no mesh under the tip
  kMeshOnly,    ///< through the mesh into nothing
  kNothing,     ///< into nothing
};

/// "fixed", "tissue only", "mesh only", "nothing".
const char* to_string(TackOutcome outcome);

/// A named point of the anatomy (a landmark the tack may be near).
struct NamedPoint {
  std::string name;
  Vec3 point = Vec3::Zero();
};

/// The record of one firing.
struct TackRecord {
  Real time = 0;                 ///< simulated time (s)
  std::size_t instrument = 0;    ///< the tacker's instrument index
  Vec3 tip = Vec3::Zero();       ///< the tip's world position when fired (m)
  TackOutcome outcome = TackOutcome::kNothing;
  std::string zone;              ///< the named zone the tip was in ("" when none): always an error
  std::size_t tissue = kNoIndex;    ///< the tissue the tack went into (not the mesh), kNoIndex when none
  std::size_t attachment = kNoIndex;  ///< Simulation::attachments() index (kFixed), kNoIndex otherwise
  SurfacePoint mesh_point;       ///< on the mesh (valid when the mesh was within reach)
  SurfacePoint tissue_point;     ///< on the tissue (valid when `tissue` != kNoIndex)
  std::string landmark;          ///< the nearest of the landmarks given ("" when none given)
  Real landmark_distance = -1;   ///< its distance from the tip (m), < 0 when none given
};

/// The tip of an instrument in the world: a point and the unit firing axis.
struct TackerTip {
  Vec3 point = Vec3::Zero();
  Vec3 axis = Vec3(0, 0, -1);
};

/// The rules' tip, else the end of the local box's long axis away from the top vertex (the
/// shaft's far end from the handle), carried by the current pose.
TackerTip tacker_tip(const Instrument& instrument, const TackerRules& rules);

/// The closest point of tissue `t`'s surface to p, and its distance (m).
struct SurfaceHit {
  SurfacePoint point;
  Real distance = std::numeric_limits<Real>::infinity();
};
SurfaceHit closest_surface_point(const TissueBody& tissue, std::uint32_t t, const Vec3& p);

/// The closest point of tissue `t`'s surface to the disc of `radius` about tip.point across
/// tip.axis (sampled at its centre and 12 points of its rim), and its distance (m).
SurfaceHit closest_surface_point(const TissueBody& tissue, std::uint32_t t, const TackerTip& tip, Real radius);

/// Fires instrument `instrument`'s tacker: finds the mesh and the nearest other tissue within
/// reach of the tip's face, attaches them when both are there (kFixed), and records the outcome, the
/// zone the tip is in and the nearest landmark. A failed attach (capacity full) leaves
/// attachment = kNoIndex with outcome kFixed; the caller reports it.
TackRecord fire_tacker(Simulation& sim, std::size_t instrument, const TackerRules& rules,
                       std::span<const NamedZone> zones, std::span<const NamedPoint> landmarks = {});

}  // namespace trocar
