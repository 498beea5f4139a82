#pragma once
/// The collision response for one step: many contacts → tissue loads and the instrument's load.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/collision/contact.h"
#include "trocar/core/types.h"
#include "trocar/instrument/instrument.h"
#include "trocar/response/contact_response.h"
#include "trocar/response/grasp.h"
#include "trocar/response/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {

/// A read-only view of a tissue in the world.
struct TissueView {
  std::span<const Vec3> positions;      ///< x_i (m)
  std::span<const Vec3> velocities;     ///< v_i (m/s); empty means at rest
  std::span<const Triangle> triangles;  ///< outward-oriented triangles
};

/// The force and torque on the instrument, summed over contacts, and the clamped copy the
/// haptic device renders.
struct InstrumentLoad {
  Vec3 raw_force = Vec3::Zero();   ///< Σ −F over applied contacts (N)
  Vec3 raw_torque = Vec3::Zero();  ///< Σ (P − o) × (−F), o the instrument's pose origin (N·m)
  Vec3 force = Vec3::Zero();       ///< raw_force scaled to |force| ≤ max_force (N)
  Vec3 torque = Vec3::Zero();      ///< raw_torque scaled by the same factor (N·m)
  bool clamped = false;            ///< the scale factor was < 1
  /// Zeroes everything.
  void clear() { *this = InstrumentLoad{}; }
  /// force, torque ← raw × min(1, max_force/|raw_force|) (no clamp for max_force ≤ 0).
  /// Scaling force and torque together keeps the line of action of the resultant.
  void clamp(Real max_force);
};

/// Counts for one call of ResponseSolver::apply.
struct ResponseStats {
  std::array<std::uint32_t, static_cast<std::size_t>(ContactStatus::kCount)> by_status{};  ///< per status
  std::uint32_t considered = 0;  ///< instrument–tissue contacts of this pair
  Real max_depth = 0;            ///< largest |D| among applied contacts (m)
  /// Contacts with the given status.
  std::uint32_t count(ContactStatus s) const { return by_status[static_cast<std::size_t>(s)]; }
};

/// The share of a contact's position correction (project, primitive) that is applied:
/// clamp(approach_speed / correction_speed, 0, 1), 1 when correction_speed ≤ 0 (ungated).
/// approach_speed is the instrument's own velocity at P along n_in (m/s).
Real correction_gate(Real approach_speed, Real correction_speed);

/// The response between one instrument and one tissue (one solver per pair: it holds that
/// pair's grasp and position corrections). No allocation in apply() after reset(), except the
/// first time loads.contacts outgrows the capacity reserved by TissueLoads::reset.
class ResponseSolver {
 public:
  /// A solver with `settings`; call reset() before apply().
  explicit ResponseSolver(const ResponseSettings& settings = {}) : settings_(settings) {}
  /// Sizes the per-vertex buffers for a tissue of `tissue_vertex_count` vertices; releases grasps.
  void reset(std::size_t tissue_vertex_count);
  /// The settings.
  const ResponseSettings& settings() const { return settings_; }
  /// The tissue's vertices were renumbered (a cut; Grasp::remodel): re-sizes, keeps the grasp.
  void remodel(std::span<const std::uint32_t> vertex_origin);
  /// Replaces the settings (method, gains, clamp).
  void set_settings(const ResponseSettings& settings) { settings_ = settings; }

  /// Processes the contacts with kind kInstrumentTissue, object_a == instrument_object and
  /// object_b == tissue_object (others are skipped): for each, grasping (step 10) or the kernel
  /// (steps 1–9); the force F is added to loads.forces of B1..B3 with P's barycentric weights
  /// (grasped vertices get none), a ContactJacobian (K, μ, n_in, weights) is appended to
  /// loads.contacts, and −F with its torque about the pose origin is added to load.raw_*;
  /// then load is clamped to settings().max_force. loads.forces must have one entry per tissue
  /// vertex. Releases every grasp when the jaws are open (jaw < grasp_closure).
  ResponseStats apply(std::span<const Contact> contacts, std::uint32_t instrument_object,
                      std::uint32_t tissue_object, const Instrument& instrument, const TissueView& tissue,
                      TissueLoads& loads, InstrumentLoad& load);

  /// Moves the held vertices with the instrument (Grasp::apply). Call after integrating.
  void apply_grasp(const Instrument& instrument, std::span<Vec3> positions, std::span<Vec3> velocities) const {
    grasp_.apply(instrument, positions, velocities);
  }
  /// `project` and `primitive`: adds the position corrections of the last apply() to positions:
  /// Δx_v = Σ_c w_vc·D_c / max(1, Σ_c w_vc) (one contact moves its vertices by w·D; vertices
  /// shared by several contacts get the weighted mean). No-op for the other methods.
  void apply_corrections(std::span<Vec3> positions) const;
  /// The grasp state.
  const Grasp& grasp() const { return grasp_; }
  /// The last applied contact's full record (for tests and the recorder).
  const ContactResponse& last() const { return last_; }

 private:
  ResponseSettings settings_;
  Grasp grasp_;
  std::vector<Vec3> correction_;          ///< Σ w·D per vertex (m)
  std::vector<Real> correction_weight_;   ///< Σ w per vertex
  std::vector<std::uint32_t> touched_;    ///< vertices with a correction this step
  ContactResponse last_;
};

}  // namespace trocar
