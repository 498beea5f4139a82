#pragma once
/// Building a real-time session from a scene: one device per instrument (its "device", or its
/// "motion" played as a scripted device), and replaying a recorded session.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/device/port_device.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/scene/scene.h"

namespace trocar {

/// The port pivot of a "mouse"-driven instrument: its scene "pivot", else default_port of its
/// starting pose (the motion's first sample, else its current pose).
PortKinematics port_kinematics(const DeviceSpec& spec, const InstrumentBody& body);

/// One RuntimeChannel per instrument of `world` from `devices` (Scene::devices, same index).
/// Throws trocar::Error naming the scene key for a driver this build lacks.
std::vector<RuntimeChannel> make_channels(const std::vector<DeviceSpec>& devices, const World& world);

/// The header of a recording of `sim` run on the runtime with `settings`, from the scene file
/// `scene_file` whose text was `scene_text` (the step records carry their own dt; the header's
/// timestep is the session's nominal one).
RecordingHeader session_header(const std::filesystem::path& scene_file, std::string scene_text,
                               const Simulation& sim, const RuntimeSettings& settings);

/// Ends a recording with the simulation's state hash after its last step.
void finish_recording(RecordingWriter& writer, const Simulation& sim);

/// What a replay found.
struct ReplayResult {
  std::uint64_t steps = 0;            ///< steps replayed
  std::uint64_t state_hash = 0;       ///< after the last one
  std::uint64_t recorded_hash = 0;    ///< the recording's
  std::string recorded_kernel_path;   ///< the recording's header ("unknown" for version 1)
  std::string kernel_path;            ///< the replay's (core/cpu_features.h)
  bool matches() const { return state_hash == recorded_hash; }  ///< bit for bit
  /// The hashes can be compared: both runs took the same kernel path, or the recording does not
  /// say which it took (then a mismatch may be the path's doing; verdict() says so).
  /// The AVX-512 kernels (the OHC's opening and box tests) give exactly the AVX2 path's contacts
  /// (the pinned hashes agree), so "avx512" and "avx2" compare as one path.
  bool comparable() const {
    const auto state_path = [](const std::string& p) { return p == "avx512" ? std::string("avx2") : p; };
    return state_path(recorded_kernel_path) == state_path(kernel_path) || recorded_kernel_path == kUnknownKernelPath;
  }
  /// "identical", "DIFFERENT" (with a note when the recording does not state its kernel path),
  /// or "recorded on avx2, replaying on portable: hashes are not comparable across kernel paths".
  std::string verdict() const;
};

/// Watches a replay (the trainee's assessment samples the session through it).
class ReplayObserver {
 public:
  virtual ~ReplayObserver() = default;
  /// Before the first step: the recorded scene (its world already moved into `sim`) and the
  /// procedure (nullptr when the scene has no task).
  virtual void start(const Scene& scene, const Simulation& sim, const Procedure* procedure) = 0;
  /// After each step, once the procedure has seen it.
  virtual void step(const Simulation& sim, const Procedure* procedure, const StepRecord& record) = 0;
  /// After the last step (the procedure and the simulation are gone once the replay returns).
  virtual void end(const Simulation& /*sim*/, const Procedure* /*procedure*/) {}
};

/// Rebuilds the session's scene from the recording (its text, meshes relative to its recorded
/// path) and redoes every recorded physics step in lock-step on this process's kernel path. Throws trocar::FileError for a
/// truncated or corrupt recording (with the byte offset).
/// `observer` (may be null) watches every step.
ReplayResult replay_recording(const std::filesystem::path& recording, ReplayObserver* observer = nullptr);

}  // namespace trocar
