#pragma once
/// One step of the simulation (docs/architecture.md): motion → instrument poses → broad
/// phase → narrow phase → response → deformation → metrics.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/detector.h"
#include "trocar/collision/ohc_broad_phase.h"
#include "trocar/electrosurgery/thermal.h"
#include "trocar/response/instrument_field.h"
#include "trocar/response/response_solver.h"
#include "trocar/response/settings.h"
#include "trocar/response/tissue_contact.h"
#include "trocar/response/tissue_response.h"
#include "trocar/sim/penetration_meter.h"
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
  /// Tissue pairs whose surfaces must not cross (scene key "tissue_contacts"); empty: none, and the
  /// step does no tissue–tissue work.
  std::vector<TissueContactPair> tissue_contacts;
  /// Solve those contacts and the tacks inside the XPBD substeps of the tissues they join, all
  /// stepped in lock-step (docs/response.md, "Tissue against tissue"); false: after the
  /// integrators, as for tissues of other integrators (scene key "tissue_coupling": "substeps",
  /// "after").
  bool couple_tissues = true;
};

/// Wall-clock time of each stage of the last step (µs).
struct StageTimings {
  double motion = 0;        ///< keyframes → instrument poses
  double broad_phase = 0;   ///< candidate pairs (0 on steps without detection)
  double narrow_phase = 0;  ///< exact triangle tests
  double response = 0;      ///< contacts → loads
  double deformation = 0;   ///< integrators, corrections, grasps, and the sdf projection
  double projection = 0;    ///< of deformation: the responses' work after the integrators beyond grasps (the sdf projection)
  double metrics = 0;       ///< penetration, tunneling, energies (and the start-surface copy)
  double electrosurgery = 0;  ///< electrodes' heat, thermal damage, and remodelling after cuts
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
  /// Deepest instrument vertex inside any closed tissue (m, ≥ 0; PenetrationReading).
  Real penetration_max = 0;
  /// Instrument vertices inside a tissue this step (summed over instrument–tissue pairs).
  std::uint32_t vertices_inside = 0;
  /// Tunneling events this step (PenetrationMeter).
  std::uint32_t tunneling_events = 0;
  Real kinetic_energy = 0;           ///< Σ ½ m v² over tissues (J)
  Real elastic_energy = 0;           ///< springs, area, volume, home springs (J; gravity excluded)
  Real max_speed = 0;                ///< fastest tissue vertex (m/s)
  /// The largest mass-weighted RMS speed of a single tissue, √(2 E_kin,t / m_t) (m/s): what
  /// core/stability.h bounds per tissue (a light tissue flung fast hides in the scene's total).
  Real tissue_rms_speed = 0;
  bool finite = true;                ///< every position and velocity is finite
  std::uint32_t cg_iterations = 0;   ///< conjugate-gradient iterations of the implicit tissues
  std::uint32_t substeps = 0;        ///< xpbd tissues: substeps (one constraint pass each)
  /// Largest constraint error a tissue's solver left (StepStats::constraint_error).
  Real constraint_error = 0;
  /// Electrosurgery (docs/electrosurgery.md): energy the electrodes put into tissue this step (J),
  /// triangles cut open and tissues remodelled (a cut or newly coagulated springs) this step.
  Real energy = 0;
  std::uint32_t triangles_cut = 0;
  std::uint32_t remodelled = 0;
  StageTimings timings;              ///< µs per stage
};

/// Where an electrode boils tissue water off (the source of its smoke): the touched surface's
/// centre and the vaporisation energy so far (a renderer emits smoke for what it adds).
struct VapourSource {
  Vec3 at = Vec3::Zero();   ///< m: centre of the surface it touched last
  Vec3 up = Vec3::UnitZ();  ///< unit, against gravity
  Real energy = 0;          ///< J put into boiling tissue water by this electrode so far
  bool burning = false;     ///< this step its pedal was down and it touched tissue (at `at`)
};

/// What electrosurgery did to one tissue so far.
struct BurnTally {
  Real energy = 0;              ///< J delivered by electrodes
  Real cut_area = 0;            ///< m² (rest) of triangles cut open and removed
  std::uint32_t cut_triangles = 0;
  Real coagulated_area = 0;     ///< m² (rest) of triangles coagulated (Ω ≥ 1), cut ones included
};

/// Runs a World. Deterministic: the same world and step sizes give bit-identical states on the
/// same build and kernel path (one thread, fixed iteration orders, sorted contacts). After the
/// first step, step() allocates nothing, takes no lock, throws nothing and logs nothing (as long
/// as the contact count stays within what the detector has already held).
///
/// A step: instrument poses (keyframes or commands) → detection → each tissue's response before
/// its integrator → the integrators → each response after its integrator → the instruments'
/// forces (clamped for the device) → energies, and the penetration meter (penetration_meter.h).
/// The step never names a response method: each tissue has one TissueResponse
/// (response/tissue_response.h).
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
  /// The pedal of instrument i's electrode (docs/electrosurgery.md): while on, an instrument with
  /// an electrode (InstrumentBody::electrode.power > 0) heats the tissue it touches, which
  /// coagulates and, where its water boils off, is cut open. No allocation.
  void set_energy(std::size_t i, bool on) { energy_on_[i] = on ? 1 : 0; }
  bool energy_on(std::size_t i) const { return energy_on_[i] != 0; }
  /// The valves of instrument i's suction-irrigator (InstrumentBody::suction): what they draw in
  /// and jet out is the renderer's (the blood's flow is; docs/electrosurgery.md). Set here so that
  /// recordings, replays and reports carry them. An instrument without that valve ignores it.
  /// No allocation.
  void set_suction(std::size_t i, bool on) { suction_on_[i] = on && world_.instruments[i].suction.suction() ? 1 : 0; }
  bool suction_on(std::size_t i) const { return suction_on_[i] != 0; }
  void set_irrigation(std::size_t i, bool on) {
    irrigation_on_[i] = on && world_.instruments[i].suction.irrigation() ? 1 : 0;
  }
  bool irrigation_on(std::size_t i) const { return irrigation_on_[i] != 0; }
  /// Opens tissue t's triangles now (scissors, a scripted cut, a test): they are removed as a cut
  /// by the electrode removes them (the tissue remodelled at once). Indices out of range are
  /// ignored. Allocates.
  void cut(std::size_t t, std::span<const std::uint32_t> triangles);
  /// Puts `joules` of heat into tissue t's triangle k at once (ThermalField::add_heat): what an
  /// electrode would put there, without one. Out-of-range indices are ignored.
  void heat(std::size_t t, std::uint32_t k, Real joules);
  /// Tissue t's heat and thermal damage per triangle.
  const ThermalField& thermal(std::size_t t) const { return thermal_[t]; }
  /// What electrosurgery did to tissue t so far.
  BurnTally burn_tally(std::size_t t) const;
  /// The wounds of the bleeding tissues and their blood (docs/electrosurgery.md, "Bleeding"): its
  /// tissue i is bleeding_tissue(i). Only the wounds' bookkeeping runs in the step (rates,
  /// seals, what they bled); the blood's flow over the surfaces is the renderer's.
  const Bleeding& bleeding() const { return bleeding_; }
  /// The world tissue of the bleeding model's tissue i.
  std::size_t bleeding_tissue(std::size_t i) const { return bleeding_tissues_[i]; }
  /// Clips wound w (a clip applier; a scripted event; a test).
  void clip(std::size_t w) { bleeding_.clip(w); }
  /// A clip applier's clip (InstrumentBody::tool "clip-applier", its "fire"): closes the open
  /// wound nearest instrument i's tip (its local origin, where the jaws meet) within `reach` (m;
  /// the jaws close on what lies between them) and returns its index, or −1 when none is that
  /// close (the clip lands on nothing). No allocation.
  std::int64_t clip_at(std::size_t i, Real reach = kClipReach);
  /// m: how far from a clip applier's tip a bleeding point is caught (its jaws are about 5 mm long).
  static constexpr Real kClipReach = 0.005;
  /// Per instrument: where its electrode boils tissue (smoke's source; zero energy if none).
  std::span<const VapourSource> vapour() const { return vapour_; }
  /// Instrument exchange through a port (scene "port"), as a surgeon does: the instrument of
  /// i's port now in the body is withdrawn (its jaws open and let go; one step later it waits
  /// outside the body) and the next instrument of that port, in scene order, is inserted at the
  /// pose the withdrawn one had, at rest; a commanded (device-driven) port stays commanded, so
  /// the device drives the new instrument. Returns the index of the inserted instrument (i itself
  /// when its port has one instrument: nothing happens). No allocation.
  std::size_t exchange(std::size_t i);
  /// The instrument of i's port that is in the body now (or being inserted).
  std::size_t active_in_port(std::size_t i) const { return port_active_[port_of_[i]]; }
  /// True while instrument i waits outside the body (parked far from everything, never touching).
  bool parked(std::size_t i) const { return phase_[i] == PortPhase::kOutside; }
  /// True while tissue t waits outside the body for its time to enter (TissueBody::enters_at).
  bool tissue_waiting(std::size_t t) const { return tissue_waiting_[t] != 0; }
  /// True while instrument i is commanded.
  bool instrument_commanded(std::size_t i) const { return commands_[i].active; }

  World& world() { return world_; }                    ///< the simulated objects
  const World& world() const { return world_; }        ///< the simulated objects
  const SimulationSettings& settings() const { return settings_; }  ///< settings
  Real time() const { return time_; }                  ///< simulated time (s)
  const StepMetrics& metrics() const { return metrics_; }  ///< last step
  /// Per-instrument force and torque of the last step (index as world().instruments).
  std::span<const InstrumentMetrics> instrument_metrics() const { return instrument_metrics_; }
  /// The raw (unclamped) force tissue t put on instrument i in the last step (N): its response's
  /// share of InstrumentMetrics::raw_force, which is their sum over the tissues. What the trainee's
  /// tissue-handling metrics read (docs/assessment.md).
  const Vec3& tissue_force(std::size_t tissue, std::size_t instrument) const {
    return tissue_forces_[tissue * loads_.size() + instrument];
  }
  /// The contacts of the last detection step (empty on steps without detection).
  std::span<const Contact> contacts() const { return contacts_; }
  /// FNV-1a 64-bit hash of the bits of every tissue's positions and velocities and every
  /// instrument's pose (rotation coefficients, translation) and jaw.
  std::uint64_t state_hash() const;
  /// The fastest tissue vertex now (where a blow-up shows first; `trocar run` names it). A
  /// non-finite speed counts as the fastest; speed 0 and tissue SIZE_MAX when there is none.
  struct FastestVertex {
    std::size_t tissue = static_cast<std::size_t>(-1);
    std::uint32_t vertex = 0;
    Real speed = 0;
    Vec3 position = Vec3::Zero();
  };
  FastestVertex fastest_vertex() const;
  /// Tissue t's collision response (its own contact points, for display).
  const TissueResponse& response(std::size_t t) const { return *responses_[t]; }
  /// Fixes two tissue surface points together (a tack); returns the attachment's index, or
  /// SIZE_MAX when it cannot (capacity full, bad tissue or triangle). No allocation.
  std::size_t attach(const AttachmentSpec& spec) { return tissue_contact_->attach(spec); }
  /// Every attachment made so far, holding or torn.
  std::span<const AttachmentState> attachments() const { return tissue_contact_->attachments(); }
  /// The tissue–tissue contact solver (its pairs and last counts).
  const TissueContactSolver& tissue_contact() const { return *tissue_contact_; }
  /// The collision detector (its timings and, for OHC, the last detection's counts).
  const CollisionDetector& detector() const { return detector_; }
  /// The same, to run a detection of one's own through its caches (a test comparing it with a
  /// fresh detector after cuts).
  CollisionDetector& detector() { return detector_; }

 private:
  void detect();
  void respond();
  void deform(Real dt);
  void measure();
  /// Electrodes → heat per triangle → thermal damage (electrosurgery.cpp).
  void burn(Real dt);
  /// Newly coagulated springs stiffened, cut triangles removed: tissue t rebuilt (remodel.cpp).
  void remodel(std::size_t t);
  /// The electrosurgery bookkeeping of tissue t sized for its model (construction, remodel).
  void size_burn(std::size_t t);

  World world_;
  SimulationSettings settings_;
  CollisionDetector detector_;
  std::vector<CollisionObject> objects_;     ///< instruments, then tissues, then rigids
  std::vector<Contact> contacts_;            ///< this step's contacts
  std::vector<InstrumentField> fields_;      ///< per instrument, when a tissue's response needs it (built once)
  std::vector<std::unique_ptr<TissueResponse>> responses_;  ///< per tissue
  std::vector<InstrumentLoad> loads_;        ///< per instrument: this step's raw load, then clamped
  std::vector<Vec3> tissue_forces_;          ///< tissue-major: each tissue's share of loads_[i].raw_force
  std::vector<Vec3> raw_before_;             ///< per instrument: raw_force before a tissue's response ran
  std::vector<Real> tissue_masses_;          ///< per tissue: Σ vertex masses (kg), for tissue_rms_speed
  /// Calls `respond` (one tissue's response adding to loads_) and credits what it added to tissue t.
  template <typename Respond>
  void credit_tissue(std::size_t t, Respond&& respond);
  std::vector<InstrumentMetrics> instrument_metrics_;
  std::unique_ptr<TissueContactSolver> tissue_contact_;  ///< tissue pairs and attachments
  std::unique_ptr<PenetrationMeter> meter_;  ///< penetration and tunneling (settings.measure_penetration)
  /// Per instrument: the pose and jaw commanded from outside, used instead of the keyframes.
  struct Command {
    bool active = false;  ///< commanded (else keyframes)
    MotionSample sample;  ///< pose and jaw
  };
  std::vector<Command> commands_;
  /// Ports: each instrument's port group, the group's instrument in use, and each instrument's
  /// phase in an exchange.
  enum class PortPhase : std::uint8_t { kInside, kWithdrawing, kOutside, kInserting };
  std::vector<std::uint32_t> port_of_;
  std::vector<std::size_t> port_active_;
  std::vector<PortPhase> phase_;
  void advance_ports();
  /// Per tissue: 1 while it waits outside (enters_at still ahead).
  std::vector<std::uint8_t> tissue_waiting_;
  /// Per tissue: its XPBD solver (null when it is not stepped in lock-step with the others: not
  /// XPBD, outside the body), state, loads and instrument contacts, and its coupled step's stats.
  std::vector<CoupledTissue> coupled_;
  std::vector<XpbdStats> coupled_stats_;
  void admit_tissues();
  // Electrosurgery (docs/electrosurgery.md).
  std::vector<std::uint8_t> energy_on_;                  ///< per instrument: pedal down
  std::vector<std::uint8_t> suction_on_, irrigation_on_; ///< per instrument: valve open
  std::vector<std::vector<Vec3>> electrode_;             ///< per instrument: its electrode's points (local)
  /// What an electrode touched this step: tissue, triangle, its share of the power (W).
  struct Touch {
    std::uint32_t tissue, triangle;
    Real watts;
  };
  std::vector<std::vector<Touch>> touches_;              ///< per instrument (capacity kept)
  std::vector<VapourSource> vapour_;                     ///< per instrument
  std::vector<Vec3> electrode_points_;                   ///< scratch: one electrode's points in the world
  std::vector<ThermalField> thermal_;                    ///< per tissue
  std::vector<std::vector<Real>> power_;                 ///< per tissue, per triangle: W this step
  std::vector<std::vector<std::uint8_t>> touched_;       ///< per tissue, per triangle: scratch
  std::vector<std::vector<std::uint8_t>> stiffened_;     ///< per tissue, per spring: coagulation applied
  /// Per tissue: structural spring by its edge (sorted vertex pair), built at the first
  /// coagulation of each model (a cut clears it).
  std::vector<std::unordered_map<std::uint64_t, std::uint32_t>> spring_of_;
  /// Scratch of a remodel (kept: coagulating without a cut allocates nothing once warm).
  std::vector<std::uint32_t> remodel_cut_, remodel_coagulating_, remodel_changed_;
  std::vector<Spring> remodel_before_;
  std::vector<std::vector<std::uint8_t>> coagulated_;    ///< per tissue, per triangle: counted as coagulated
  std::vector<BurnTally> burns_;                         ///< per tissue
  std::vector<Real> next_remodel_;                       ///< per tissue: earliest time of its next remodel (s)
  Bleeding bleeding_;                                    ///< wounds of the bleeding tissues
  std::vector<std::size_t> bleeding_tissues_;            ///< bleeding model's tissue → world tissue
  std::vector<std::int64_t> bleeding_index_;             ///< world tissue → bleeding model's (−1: none)
  /// Wounds where tissue t bleeds from (after a cut, tear or burn there), unless one is open within
  /// 3 mm; `rest` is the place in the rest shape.
  void open_wound(std::size_t t, const Vec3& rest);
  void bleed(Real dt);                                   ///< seals, tears and the wounds' step
  StepMetrics metrics_;
  Real time_ = 0;
  Real dt_ = 0;  ///< this step's dt (s)
  std::uint64_t steps_ = 0;
  Real next_detection_ = -1;  ///< time of the next detection (s); < 0 before the first
};

/// The hash as 16 lower-case hex digits.
std::string hash_hex(std::uint64_t hash);

}  // namespace trocar
