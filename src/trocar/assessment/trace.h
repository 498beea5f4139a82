#pragma once
/// What a session did, sampled once per physics step (docs/assessment.md): each instrument's tip
/// and shaft, the force it put on tissue, each tissue's load, and the procedure's events. Plain
/// data: the metrics, the proficiency scoring and the report read only this, so that they are
/// tested on synthetic traces (a line, a circle, a pause) as on a replayed session.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// One instrument over the session (every vector has one entry per sample).
struct InstrumentTrace {
  std::string name;             ///< scene name ("grasper_right")
  std::string tool;             ///< "grasper", "tacker", … ("custom")
  std::string hand;             ///< "right" or "left": the port it enters by (bimanual metrics)
  std::vector<Vec3> tip;        ///< m, world
  std::vector<Vec3> axis;       ///< unit, world, along the shaft (tip → handle)
  std::vector<Real> force;      ///< N, |force on the instrument from tissue| (what it puts on tissue)
  std::vector<std::uint8_t> present;  ///< 1 while in the body (not parked out of its port)
  std::vector<std::uint8_t> in_view;  ///< 1 while the tip is inside the laparoscope's frustum
};

/// One tissue's load: Σ over instruments of |the force its response put on the instrument| (N, per
/// sample; Simulation::tissue_force).
struct TissueTrace {
  std::string name;
  bool prosthetic = false;   ///< the task's prosthetic mesh: not tissue (no tissue-handling metric)
  std::vector<Real> force;
};

/// A procedure event (procedure/procedure.h TaskEvent, as text).
struct TraceEvent {
  Real time = 0;           ///< s
  std::string kind;        ///< "tack", "zone force", "vessel grasped", …
  bool error = false;
  Vec3 place = Vec3::Zero();
  std::string zone;
  std::string text;
};

/// A task step and when it was done (< 0: not done).
struct TraceStep {
  std::string name;
  Real done_at = -1;
};

/// The task's outcome at the end.
struct TraceTask {
  bool present = false;         ///< the scene states a task
  std::vector<TraceStep> steps;
  int tacks = 0, fixed_tacks = 0, zone_tacks = 0, tissue_only_tacks = 0;
  Real coverage = 0;            ///< share of the region the mesh must cover
  Real sac_fraction = 0;        ///< share of the sac reduced
  /// Every step done (true when the scene states no task).
  bool complete() const {
    return !present || std::all_of(steps.begin(), steps.end(), [](const TraceStep& s) { return s.done_at >= 0; });
  }
};

/// Electrosurgery and bleeding at the end (docs/electrosurgery.md).
struct TraceEnergy {
  bool present = false;         ///< the scene can burn or bleed (an electrode, a bleeding tissue)
  Real energy = 0;              ///< J the electrodes put into tissue
  Real coagulated_area = 0;     ///< m², all tissues
  Real cut_area = 0;            ///< m², all tissues
  Real blood_loss = 0;          ///< m³ all wounds bled
  int wounds = 0, wounds_open = 0;
  Real haemostasis_time = 0;    ///< s, the mean time the closed wounds bled (0: none closed)
};

struct SessionTrace {
  std::string scene;                     ///< scene name
  Real dt = 0;                           ///< s between samples
  std::vector<Real> time;                ///< s: the start (0), then the end of each step
  std::vector<InstrumentTrace> instruments;
  std::vector<TissueTrace> tissues;
  std::vector<TraceEvent> events;
  TraceTask task;
  TraceEnergy energy;
  /// s: the first step whose state was not stable (core/stability.h), < 0 when none. After it the
  /// numbers are the blow-up's, not the trainee's: the session cannot be assessed.
  Real unstable_at = -1;
  std::size_t samples() const { return time.size(); }
};

}  // namespace trocar
