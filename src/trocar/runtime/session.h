#pragma once
/// Building a real-time session from a scene: one device per instrument (its "device", or its
/// "motion" played as a scripted device), and replaying a recorded session.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "trocar/runtime/runtime.h"
#include "trocar/scene/scene.h"

namespace trocar {

/// One RuntimeChannel per instrument of `world` from `devices` (Scene::devices, same index).
/// Throws trocar::Error naming the scene key for a driver this build lacks.
std::vector<RuntimeChannel> make_channels(const std::vector<DeviceSpec>& devices, const World& world);

/// What a replay found.
struct ReplayResult {
  std::uint64_t steps = 0;            ///< steps replayed
  std::uint64_t state_hash = 0;       ///< after the last one
  std::uint64_t recorded_hash = 0;    ///< the recording's
  bool matches() const { return state_hash == recorded_hash; }  ///< bit for bit
};

/// Rebuilds the session's scene from the recording (its text, meshes relative to its recorded
/// path) and redoes every recorded physics step in lock-step. Throws trocar::FileError for a
/// truncated or corrupt recording (with the byte offset).
ReplayResult replay_recording(const std::filesystem::path& recording);

}  // namespace trocar
