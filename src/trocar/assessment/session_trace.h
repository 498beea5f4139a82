#pragma once
/// A session recording replayed and sampled into a SessionTrace (docs/assessment.md, "From a
/// recording"): the replay redoes every recorded step (runtime/session.h), so the trace is the
/// session's own, bit for bit, and needs nothing but the recording.
#include <filesystem>

#include "trocar/assessment/trace.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/camera.h"

namespace trocar {

struct TracedSession {
  SessionTrace trace;
  ReplayResult replay;   ///< the replay's verdict on the recording's state hash
};

/// Replays `recording` and samples it; `also` (may be null) watches the same replay (the report's
/// frames of errors are rendered through it). Throws trocar::FileError for a bad recording.
TracedSession trace_recording(const std::filesystem::path& recording, ReplayObserver* also = nullptr);

/// The samples taken of a replay (or of a simulation a caller steps itself): start() once, step()
/// after every step, finish() with the procedure at the end.
class TraceSampler final : public ReplayObserver {
 public:
  void start(const Scene& scene, const Simulation& sim, const Procedure* procedure) override;
  void step(const Simulation& sim, const Procedure* procedure, const StepRecord& record) override;
  /// The events and the task's outcome from the procedure; returns the trace.
  SessionTrace finish(const Procedure* procedure, const Simulation* sim = nullptr);

 private:
  void sample(const Simulation& sim);

  SessionTrace trace_;
  CameraView view_;  ///< the scope's (the scene's first camera), at the monitor's 16:9
  Real tissue_mass_ = 0;  ///< kg, Σ over tissues: the stability bound's scale
};

}  // namespace trocar
