#pragma once
/// One step of the simulation (docs/architecture.md): motion → instrument poses → broad
/// phase → narrow phase → response → deformation → metrics.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/detector.h"
#include "trocar/collision/ohc_broad_phase.h"
#include "trocar/geometry/signed_distance.h"
#include "trocar/response/contact_projection.h"
#include "trocar/response/instrument_field.h"
#include "trocar/response/response_solver.h"
#include "trocar/response/settings.h"
#include "trocar/response/solver_contact.h"
#include "trocar/sim/sheet_boundary.h"
#include "trocar/sim/world.h"

namespace trocar {

/// How the simulation detects and responds (scene keys `collision` and `response`).
struct SimulationSettings {
  BroadPhaseKind broad_phase = BroadPhaseKind::kOhc;  ///< scene collision.broad_phase
  Real cell_size = 0;             ///< OHC cell edge (m); 0 = auto (scene "auto")
  /// Time between two detections (s); ≤ 0 = every step. Between detections the step has no
  /// contacts (a slow detector that the instrument outruns; docs/scene.md, `collision.period`).
  Real collision_period = 0;
  ResponseSettings response;      ///< method, gains, clamp
  bool measure_penetration = true;  ///< compute penetration and tunneling metrics each step
};

/// Wall-clock time of each stage of the last step (µs).
struct StageTimings {
  double motion = 0;        ///< keyframes → instrument poses
  double broad_phase = 0;   ///< candidate pairs (0 on steps without detection)
  double narrow_phase = 0;  ///< exact triangle tests
  double response = 0;      ///< contacts → loads
  double deformation = 0;   ///< integrators, corrections, grasps, and the sdf projection
  double projection = 0;    ///< of deformation: the sdf response's projection (0 for other methods)
  double metrics = 0;       ///< penetration, tunneling, energies (and the start-surface copy)
  double step = 0;          ///< the whole step
};

/// Force and torque on one instrument in the last step.
struct InstrumentMetrics {
  Vec3 force = Vec3::Zero();   ///< clamped force the device renders (N), Σ over tissues
  Vec3 torque = Vec3::Zero();  ///< torque about the pose origin (N·m), same scale
  Vec3 raw_force = Vec3::Zero();  ///< unclamped force (N)
};

/// What the last step did, measured after the response (and after the deformation).
struct StepMetrics {
  Real time = 0;                     ///< simulated time at the end of the step (s)
  std::uint64_t step_index = 0;      ///< steps done so far (1 after the first)
  bool detected = false;             ///< the detector ran this step
  std::uint32_t contacts = 0;        ///< instrument–tissue contacts this step (triangle pairs)
  std::uint32_t contacts_applied = 0;  ///< of those, contacts that produced a force
  /// Deepest instrument vertex inside any closed tissue (m, ≥ 0), signed distance to the
  /// deformed surface with angle-weighted pseudonormals.
  Real penetration_max = 0;
  /// Instrument vertices inside a tissue this step (summed over instrument–tissue pairs).
  std::uint32_t vertices_inside = 0;
  /// Tunneling events this step (see Simulation's class comment).
  std::uint32_t tunneling_events = 0;
  Real kinetic_energy = 0;           ///< Σ ½ m v² over tissues (J)
  Real elastic_energy = 0;           ///< springs, area, volume, home springs (J; gravity excluded)
  Real max_speed = 0;                ///< fastest tissue vertex (m/s)
  bool finite = true;                ///< every position and velocity is finite
  std::uint32_t cg_iterations = 0;   ///< conjugate-gradient iterations of the implicit tissues
  std::uint32_t substeps = 0;        ///< xpbd tissues: substeps (one constraint pass each)
  /// Largest constraint error a tissue's solver left (StepStats::constraint_error).
  Real constraint_error = 0;
  StageTimings timings;              ///< µs per stage
};

/// Runs a World. Deterministic: the same world and step sizes give bit-identical states on the
/// same build (one thread, fixed iteration orders, sorted contacts). After the first step,
/// step() allocates nothing, takes no lock, throws nothing and logs nothing (as long as the
/// contact count stays within what the detector has already held).
///
/// Metrics (docs/scene.md). Penetration: for each closed tissue whose bounding box (grown by 1 nm
/// against rounding) holds some instrument vertex, the tissue's MeshDistance is
/// refitted to the deformed positions once per step and every instrument vertex in that box is
/// queried, seeded with the triangle that vertex was nearest to last time; a vertex outside that
/// box is outside the tissue (outside the hull of its vertices; its distance is recorded as
/// +inf: only the sign of an outside vertex's distance enters the metrics). The queries go in
/// batches of nearby vertices (MeshDistance::signed_distances; each result is the vertex's own
/// exact query). depth = max(0, −signed distance). Open tissues
/// (sheets) have no inside and are not measured. Tunneling, per instrument vertex and tissue:
/// (a) the vertex was outside at the end of the previous step, is inside now, is inside the
/// surface as it stood when this step's detection ran (before this step's deformation: the
/// instrument's own motion carried it across, not the tissue springing over it after the
/// response), and no contact of this step involves an instrument triangle incident to it (it
/// crossed the surface unseen: between detections, or too fast for the discrete test); or (b)
/// its depth first exceeds the instrument's thickness (counted when it goes from ≤ thickness to
/// > thickness).
class Simulation {
 public:
  /// Takes the world; instruments are placed at their motion's t = 0 pose (at rest).
  Simulation(World world, const SimulationSettings& settings);
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Advances by dt seconds (> 0) and returns the step's metrics.
  const StepMetrics& step(Real dt);

  /// Drives instrument i from outside (a device through the runtime, a replay) instead of its
  /// keyframes: the next steps move it to `pose` with jaw closure `jaw` (the velocity comes from
  /// consecutive poses, as with keyframes). Holds until the next command or release_instrument().
  /// No allocation.
  void command_instrument(std::size_t i, const Pose& pose, Real jaw);
  /// Puts instrument i at `pose`, at rest, and commands it there (before the first step: a
  /// device's first sample, without the jump a move would give).
  void place_instrument(std::size_t i, const Pose& pose, Real jaw);
  /// Returns instrument i to its keyframes.
  void release_instrument(std::size_t i);
  /// True while instrument i is commanded.
  bool instrument_commanded(std::size_t i) const { return commands_[i].active; }

  World& world() { return world_; }                    ///< the simulated objects
  const World& world() const { return world_; }        ///< the simulated objects
  const SimulationSettings& settings() const { return settings_; }  ///< settings
  Real time() const { return time_; }                  ///< simulated time (s)
  const StepMetrics& metrics() const { return metrics_; }  ///< last step
  /// Per-instrument force and torque of the last step (index as world().instruments).
  std::span<const InstrumentMetrics> instrument_metrics() const { return instrument_metrics_; }
  /// The contacts of the last detection step (empty on steps without detection).
  std::span<const Contact> contacts() const { return contacts_; }
  /// FNV-1a 64-bit hash of the bits of every tissue's positions and velocities and every
  /// instrument's pose (rotation coefficients, translation) and jaw.
  std::uint64_t state_hash() const;
  /// Tissue t's contact inside the xpbd solver (null for the other integrators).
  const InstrumentContacts* solver_contacts(std::size_t t) const { return solver_contacts_[t].get(); }
  /// The collision detector (its timings and, for OHC, the last detection's counts).
  const CollisionDetector& detector() const { return detector_; }

 private:
  void detect();
  void respond();
  void deform(Real dt);
  void measure();
  void measure_penetration(std::size_t tissue);
  /// Queries the instrument's vertices in inside_box (the tissue's box, grown by 1 nm; for a
  /// sheet, by the step's motion too).
  void measure_pair(std::size_t instrument, std::size_t tissue, const Aabb& inside_box, bool sheet);
  /// For an open tissue (sheet_crossing.cpp): counts vertex v's tunneling event if it changed
  /// sides of the sheet on its own this step without a contact, and returns the distance to
  /// keep for it (NaN, side unknown, when its closest feature is on the sheet's border).
  Real sheet_side(const InstrumentBody& body, std::size_t instrument, std::size_t tissue, std::uint32_t v,
                  const SignedDistanceResult& r);
  /// Tissue t's surface as this step's detection saw it (start_distances_, refitted to
  /// start_positions_ once per tissue measurement when it differs).
  const MeshDistance& start_surface(std::size_t tissue);
  /// Counts vertex v of an instrument, at signed distance d < 0 inside a tissue, and its
  /// tunneling event if any.
  void count_inside(const InstrumentBody& body, std::size_t instrument, std::size_t tissue,
                    std::uint32_t v, Real d);
  ResponseSolver& solver(std::size_t instrument, std::size_t tissue) {
    return solvers_[instrument * world_.tissues.size() + tissue];
  }
  /// Method sdf: moves tissue t out of every instrument and adds the constraint's force to the
  /// instruments' raw loads.
  void project_contacts(std::size_t tissue, Real dt);

  World world_;
  SimulationSettings settings_;
  CollisionDetector detector_;
  std::vector<CollisionObject> objects_;     ///< instruments, then tissues, then rigids
  std::vector<Contact> contacts_;            ///< this step's contacts
  std::vector<ResponseSolver> solvers_;      ///< per (instrument, tissue) pair
  std::vector<ContactProjector> projectors_; ///< per (instrument, tissue) pair (method sdf)
  std::vector<InstrumentField> fields_;      ///< per instrument (method sdf or an xpbd tissue; built once)
  /// Per tissue: its contact inside the xpbd solver (null for the other integrators).
  /// (The detector still runs for them: its triangle pairs are what the renderer draws, the
  /// recording keeps and the tunneling metric counts as seen; the solver finds its own.)
  std::vector<std::unique_ptr<InstrumentContacts>> solver_contacts_;
  std::vector<InstrumentLoad> loads_;        ///< per instrument: this step's raw load, then clamped
  std::vector<InstrumentMetrics> instrument_metrics_;
  std::vector<std::unique_ptr<MeshDistance>> distances_;  ///< per tissue (null without metrics)
  std::vector<SheetBoundary> sheets_;  ///< per tissue: the border of an open one (empty when closed)
  std::vector<Real> reach_;            ///< per instrument: farthest vertex from its pose origin (m)
  Real dt_ = 0;                        ///< this step's dt (s)
  /// Per measured tissue: its positions before this step's deformation (the surface the
  /// detection saw) and a MeshDistance for them, used only when a tunneling candidate asks. The
  /// two MeshDistances swap at each refit, so this one holds the previous refit's surface; it
  /// is refitted only when that is not bit-identical to start_positions_ (e.g. after a step
  /// without measurement, or positions changed between steps).
  std::vector<std::vector<Vec3>> start_positions_;
  std::vector<std::unique_ptr<MeshDistance>> start_distances_;
  /// Per (instrument, tissue) pair: last signed distance of each instrument vertex (m);
  /// NaN before the first measurement, +inf outside the tissue's box.
  std::vector<std::vector<Real>> previous_distance_;
  /// Per (instrument, tissue) pair: the tissue triangle each instrument vertex was last nearest
  /// to (MeshDistance::kNoTriangle if none), the seed of its next query.
  std::vector<std::vector<std::uint32_t>> nearest_triangle_;
  std::vector<std::vector<std::uint8_t>> touched_;  ///< per instrument: vertex in a contact now
  /// Per (instrument, tissue) pair, open tissues only: 1 while an instrument vertex is on the far
  /// side of the sheet from where it came (it crossed the sheet's interior, side known on both
  /// steps), so its distance to the sheet is a penetration depth; 0 once it crosses back or its
  /// side becomes unknown (sim/sheet_crossing.cpp).
  std::vector<std::vector<std::uint8_t>> through_;
  bool start_refitted_ = false;  ///< start_distances_ of the tissue being measured is current
  /// Per instrument: its vertex ids in a spatially coherent order (the penetration queries go in
  /// batches of consecutive vertices in the tissue's box).
  std::vector<std::vector<std::uint32_t>> query_order_;
  MeshDistance::BatchScratch query_scratch_;  ///< candidate triangles of one query batch
  /// Per instrument: the pose and jaw commanded from outside, used instead of the keyframes.
  struct Command {
    bool active = false;  ///< commanded (else keyframes)
    MotionSample sample;  ///< pose and jaw
  };
  std::vector<Command> commands_;
  StepMetrics metrics_;
  Real time_ = 0;
  std::uint64_t steps_ = 0;
  Real next_detection_ = -1;  ///< time of the next detection (s); < 0 before the first
};

/// The hash as 16 lower-case hex digits.
std::string hash_hex(std::uint64_t hash);

}  // namespace trocar
