#pragma once
/// A task being done (docs/procedure.md): its steps in order with their completion tests, the
/// tacks fired, and the event log (steps done, tacks, errors with time and place). Built from a
/// TaskSpec, the Simulation's world (tissue names → indices), the scene's zones and landmarks;
/// update() after every step; fire_tacker() when a tacker fires; view() for displays.
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/geometry/zone.h"
#include "trocar/procedure/actions.h"
#include "trocar/procedure/task.h"
#include "trocar/procedure/task_measures.h"
#include "trocar/procedure/task_view.h"
#include "trocar/procedure/tacker.h"
#include "trocar/sim/simulation.h"

namespace trocar {

/// What an event records.
enum class TaskEventKind : std::uint8_t {
  kStepDone,       ///< a step completed (a note)
  kTack,           ///< a tack fired (a note; its outcome in the text)
  kTackInZone,     ///< error: a tack fired with the tip in a named zone
  kTackNotHeld,    ///< error: a tack through mesh and tissue that could not be attached
  kZoneForce,      ///< error: a named zone touched with more than the stated force
  kVesselGrasped,  ///< error: a vessel held by closed jaws
  kMeshDropped,    ///< error: the mesh let go of and fallen
  kZoneBurnt,      ///< error: an electrode burning in a named zone
  kBleeding,       ///< error: a vessel cut, torn or burnt open (a wound bleeds)
  kHaemostasis,    ///< a bleeding wound sealed or clipped (a note; the time it took in the text)
  kTackTornOut,    ///< a tack that held mesh to tissue let go: pulled out, or its tissue cut (a note)
};

/// "step done", "tack", "tack in zone", "tack not held", "zone force", "vessel grasped",
/// "mesh dropped", "zone burnt", "bleeding", "haemostasis", "tack torn out".
const char* to_string(TaskEventKind kind);

/// One entry of the log.
struct TaskEvent {
  Real time = 0;                  ///< simulated time (s)
  TaskEventKind kind = TaskEventKind::kStepDone;
  bool error = false;
  Vec3 place = Vec3::Zero();      ///< where (m): the tip, the tack, the mesh's centroid
  std::string zone;               ///< the zone concerned ("" when none)
  std::string text;               ///< one line for people
};

/// The three steps.
enum class TaskStep : std::uint8_t { kSacReduced = 0, kMeshPlaced = 1, kMeshFixed = 2 };
inline constexpr std::size_t kTaskSteps = 3;

/// One step's state and the measures of its last evaluation.
struct StepStatus {
  StepState state = StepState::kPending;
  Real done_at = -1;  ///< s, < 0 while not done
};

/// The measures the completion tests read (the last evaluation of each; 0 before it).
struct TaskMeasures {
  Real sac_fraction = 0;     ///< sac area on the cavity side of the wall / sac area
  Real coverage = 0;         ///< share of the required region under the mesh
  Real fold_area = 0;        ///< m², mesh area folded over
  int fixed_tacks = 0;       ///< tacks through the mesh into tissue, still holding (and counted)
  int landmarks_tacked = 0;  ///< tack landmarks with such a tack within the radius
  int zone_tacks = 0;        ///< tacks with the tip in a named zone
};

/// The procedure. Not copyable (holds per-instrument state sized once). It is also the handler
/// of the fire action (procedure/actions.h): a press fires the port's instrument if it is a tacker.
class Procedure final : public ActionHandler {
 public:
  /// Resolves the spec's tissue names and landmarks; throws trocar::Error naming the missing one.
  Procedure(TaskSpec spec, const World& world, std::span<const NamedZone> zones,
            const std::map<std::string, Vec3>& landmarks);

  /// Evaluates the rules after a step: the error monitors, then the active step's test (a step
  /// completes only after the one before it; done is final). Cheap: one scan of the active
  /// step's tissue; allocates nothing but an event's text when one is logged.
  void update(const Simulation& sim);

  /// Fires instrument `instrument` as a tacker (fire_tacker with the task's rules, zones and tack
  /// landmarks); records the tack and logs it (and the error when it is in a zone).
  const TackRecord& fire_tacker(Simulation& sim, std::size_t instrument);
  /// The fire action: fire_tacker() when instrument i is a "tacker" (InstrumentBody::tool); a
  /// press on any other instrument does nothing.
  void fire(Simulation& sim, std::size_t instrument) override;
  /// Gives instrument i's tacker tip (local frame) instead of the default from its box.
  void set_tacker_tip(std::size_t instrument, const Vec3& tip_local, const Vec3& axis_local);

  const TaskSpec& spec() const { return spec_; }
  const StepStatus& step(TaskStep s) const { return steps_[static_cast<std::size_t>(s)]; }
  const TaskMeasures& measures() const { return measures_; }
  std::span<const TackRecord> tacks() const { return tacks_; }
  std::span<const TaskEvent> events() const { return events_; }
  std::size_t error_count() const;
  bool complete() const { return steps_[kTaskSteps - 1].state == StepState::kDone; }
  /// "sac reduced", "mesh placed", "mesh fixed".
  static const char* step_name(TaskStep s);

  /// The panel: steps with their state and a one-line detail, and the events.
  TaskView view() const;

  std::size_t sac_tissue() const { return sac_; }
  std::size_t mesh_tissue() const { return mesh_; }
  const WallPlane& wall() const { return wall_; }

 private:
  void watch_zones(const Simulation& sim);
  void watch_vessels(const Simulation& sim);
  void watch_mesh(const Simulation& sim);
  void watch_burns(const Simulation& sim);
  /// Logs each fixed tack that stopped holding since the last update.
  void watch_tacks(const Simulation& sim);
  bool evaluate(const Simulation& sim, TaskStep s);
  bool mesh_has_holding_tack(const Simulation& sim) const;
  Vec3 mesh_centroid(const Simulation& sim) const;
  void log(Real time, TaskEventKind kind, bool error, const Vec3& place, std::string zone, std::string text);

  TaskSpec spec_;
  std::size_t sac_ = kNoIndex, mesh_ = kNoIndex, wall_tissue_ = kNoIndex;
  std::vector<std::size_t> vessels_;
  std::vector<std::string> tissue_names_, instrument_names_;
  std::vector<NamedZone> zones_;
  std::vector<NamedPoint> tack_landmarks_;
  WallPlane wall_;
  CoverageRegion coverage_;
  std::vector<TackerRules> tacker_rules_;  ///< per instrument
  StepStatus steps_[kTaskSteps];
  TaskMeasures measures_;
  std::vector<TackRecord> tacks_;
  std::vector<std::uint8_t> tack_let_go_;  ///< per tack: its letting go was logged
  std::vector<TaskEvent> events_;
  /// Per (instrument, zone): the current touching episode.
  struct ZoneEpisode {
    bool touching = false;   ///< in an episode
    bool reported = false;   ///< its error has been logged
    Real last_touch = -1;    ///< s
  };
  std::vector<ZoneEpisode> zone_episodes_;      ///< instrument-major
  /// Per (instrument, zone): burnt in the current press of its pedal (reported once a press).
  std::vector<std::uint8_t> zone_burnt_;
  std::size_t wounds_seen_ = 0;                 ///< wounds logged as bleeding
  std::vector<std::uint8_t> wound_closed_;      ///< per wound logged: its haemostasis logged
  std::vector<std::uint8_t> vessel_held_;       ///< per (instrument, vessel): held last update
  bool mesh_held_ = false;
  bool mesh_watch_ = false;                     ///< released and not yet fallen or re-held
  Vec3 mesh_release_centroid_ = Vec3::Zero();
  Vec3 gravity_dir_ = Vec3::Zero();
};

}  // namespace trocar
