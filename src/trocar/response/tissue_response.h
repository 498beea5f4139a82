#pragma once
/// One interface for every collision response, so that the step never names a method: a tissue's
/// response turns the step's contacts into tissue loads before the integrator, repairs and reports
/// after it, and says which instrument vertices it answered itself (docs/response.md, "Methods").
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "trocar/collision/contact.h"
#include "trocar/core/types.h"
#include "trocar/instrument/instrument.h"
#include "trocar/response/instrument_field.h"
#include "trocar/response/response_solver.h"
#include "trocar/response/settings.h"
#include "trocar/response/solver_contact.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {

/// The tissue a response acts on (its pieces live in the caller's world; they outlive the
/// response and never move).
struct ResponseTissue {
  const MassSpringSettings* settings = nullptr;  ///< the model (rest shape, masses, fixed)
  MassSpringState* state = nullptr;              ///< positions and velocities, corrected in place
  TissueLoads* loads = nullptr;                  ///< this step's external forces
  MassSpringIntegrator* integrator = nullptr;    ///< the tissue's integrator
  std::uint32_t object = 0;                      ///< the tissue's index among the detector's objects
};

/// One instrument as a response sees it; its detector object index is its position in the list.
struct ResponseInstrument {
  const Instrument* instrument = nullptr;
  /// The instrument's signed distance field (built once, shared by every tissue), or null when no
  /// tissue's response needs it (needs_instrument_field()).
  const InstrumentField* field = nullptr;
  Real thickness = 0;  ///< twice the smallest half-extent of its OBB (m)
};

/// What a tissue's response did this step, added up over the tissues.
struct ResponseTally {
  std::uint32_t contacts = 0;  ///< contacts considered (detected pairs, or vertices the solver moved)
  std::uint32_t applied = 0;   ///< of those, the ones that produced a force or a correction
  double after_us = 0;         ///< time spent in after_integration beyond grasps (µs)
};

/// A tissue's collision response. Calls per step, in order: before_integration (contacts →
/// loads), the integrator, after_integration. `loads[i]` is instrument i's raw load: each call
/// adds its force and torque to it. No allocation after the first steps.
class TissueResponse {
 public:
  virtual ~TissueResponse() = default;
  /// Before the tissue's integrator: contacts → forces on the tissue (ResponseTissue::loads) and
  /// on the instruments.
  virtual void before_integration(std::span<const Contact> contacts, std::span<InstrumentLoad> loads,
                                  ResponseTally& tally) = 0;
  /// After the integrator: position corrections, grasps, projections, and the forces they imply.
  virtual void after_integration(std::span<const Contact> contacts, Real dt, std::span<InstrumentLoad> loads,
                                 ResponseTally& tally) = 0;
  /// Per vertex of instrument i: 1 when this response found and answered that vertex's contact
  /// itself this step (the tunneling metric counts it as seen); empty when it answers only the
  /// detected pairs.
  virtual std::span<const std::uint8_t> instrument_hits(std::size_t /*instrument*/) const { return {}; }
  /// The contacts with instrument i that this response answered itself, for display (empty when
  /// the detected pairs are its contacts).
  virtual std::span<const SolverContactPoint> contact_points(std::size_t /*instrument*/) const { return {}; }
  /// Tissue vertices instrument i's closed jaws hold now (0 when none). No allocation.
  virtual std::size_t held_vertices(std::size_t /*instrument*/) const { return 0; }
  /// The tissue's model changed (a cut or coagulation: Simulation's remodelling): `tissue` is the
  /// new one (its pieces may live elsewhere now), `vertex_origin` maps each new vertex to the old
  /// one it copies. Re-sizes for it and keeps what the jaws hold (every copy of a held vertex
  /// stays held). Allocates.
  virtual void remodel(const ResponseTissue& tissue, std::span<const std::uint32_t> vertex_origin) = 0;
};

/// True when a tissue on `integrator` with these settings needs the instruments' signed distance
/// fields (the sdf projection, contact inside the xpbd solver).
bool needs_instrument_field(IntegratorKind integrator, const ResponseSettings& settings);

/// The response for one tissue: contact inside the solver for an xpbd tissue (it registers itself
/// with the integrator), else the settings' method: a penalty force (obb, primitive, normal,
/// project) or the penalty pass followed by the sdf projection (sdf).
std::unique_ptr<TissueResponse> make_tissue_response(const ResponseTissue& tissue,
                                                     std::span<const ResponseInstrument> instruments,
                                                     const ResponseSettings& settings);

}  // namespace trocar
