#pragma once
/// The session recording (docs/recording.md): a header, then blocks of fixed-size little-endian
/// records, each block checked by a 64-bit FNV-1a of its payload, so that a killed process leaves
/// a file readable up to its last complete block.
///
///   header  "TROCREC1" u32 version u32 instruments f64 haptic_rate_hz f64 timestep_s u32 mode
///           [version 2: u64 kernel_path_bytes, kernel path (ASCII, core/cpu_features.h)]
///           u64 scene_path_bytes, scene path (UTF-8), u64 scene_text_bytes, scene text
///   block   "TRBK" u32 record_count u32 payload_bytes u32 reserved u64 fnv1a(payload), payload
///   record  TickRecord | StepRecord | EndRecord (first field: u32 type, second: u32 bytes)
#include <array>
#include <cstdint>

#include "trocar/runtime/local_contact_model.h"

namespace trocar {

inline constexpr char kRecordingMagic[8] = {'T', 'R', 'O', 'C', 'R', 'E', 'C', '1'};
inline constexpr char kBlockMagic[4] = {'T', 'R', 'B', 'K'};
/// The version written. Version 1 (no kernel path) still reads, its kernel path "unknown".
inline constexpr std::uint32_t kRecordingVersion = 2;
/// The oldest version read.
inline constexpr std::uint32_t kRecordingOldestVersion = 1;
/// The kernel path of a recording whose header does not state one (version 1).
inline constexpr const char* kUnknownKernelPath = "unknown";

/// Record types.
enum class RecordType : std::uint32_t { kTick = 1, kStep = 2, kEnd = 3 };

/// A pose as 7 doubles: quaternion w, x, y, z, then translation x, y, z (m).
using PoseWords = std::array<double, 7>;

/// One instrument in one haptic tick.
struct TickInstrument {
  PoseWords device_pose{};                ///< device pose mapped into the world
  PoseWords proxy_pose{};                 ///< the pose sent to physics (world; held while the device is away)
  std::array<double, 3> force{};          ///< force rendered to the device (N, world)
  double jaw = 0;                         ///< jaw closure 0…1
  std::uint32_t status = 0;               ///< DeviceStatus
  std::uint32_t engaged = 0;              ///< 1 once the safe start let force through
  std::uint64_t model_step = 0;           ///< physics step of the model the force came from
};

/// One haptic tick.
struct TickRecord {
  std::uint32_t type = static_cast<std::uint32_t>(RecordType::kTick);  ///< kTick
  std::uint32_t bytes = sizeof(TickRecord);                            ///< record size
  std::uint64_t tick = 0;           ///< tick index (0-based)
  std::int64_t time_ns = 0;         ///< start of the tick since the runtime started (ns)
  float period_us = 0;              ///< time since the previous tick's start (µs)
  float compute_us = 0;             ///< the tick's own compute (µs)
  std::uint32_t instruments = 0;    ///< entries used below
  std::uint32_t reserved = 0;
  std::array<TickInstrument, kMaxRuntimeInstruments> instrument{};  ///< by instrument index
};

/// What physics stepped one instrument with.
struct StepInstrument {
  PoseWords pose{};                 ///< commanded pose (world)
  double jaw = 0;                   ///< commanded jaw
  std::uint32_t mode = 0;           ///< 0 keyframes, 1 commanded, 2 placed (reset at rest)
  /// Actions pressed before this step on this instrument's port (procedure/actions.h bits;
  /// always 0 in recordings made before actions existed, whose word was reserved).
  std::uint32_t actions = 0;
  std::array<double, 3> force{};    ///< resulting force on the instrument (N, clamped)
};

/// One physics step: everything replay needs to redo it, and its module timings.
struct StepRecord {
  std::uint32_t type = static_cast<std::uint32_t>(RecordType::kStep);  ///< kStep
  std::uint32_t bytes = sizeof(StepRecord);                            ///< record size
  std::uint64_t step = 0;          ///< step index (1 = the first)
  std::int64_t time_ns = 0;        ///< end of the step since the runtime started (ns)
  double dt = 0;                   ///< s
  /// µs: broad phase, narrow phase, response, deformation, projection, whole step, model build.
  std::array<float, 7> timing_us{};
  std::uint32_t instruments = 0;   ///< entries used below
  std::uint32_t contacts = 0;      ///< contacts of the step
  std::uint32_t reserved = 0;
  std::array<StepInstrument, kMaxRuntimeInstruments> instrument{};  ///< by instrument index
};

/// The last record of a complete recording.
struct EndRecord {
  std::uint32_t type = static_cast<std::uint32_t>(RecordType::kEnd);  ///< kEnd
  std::uint32_t bytes = sizeof(EndRecord);                            ///< record size
  std::uint64_t steps = 0;          ///< step records written
  std::uint64_t ticks = 0;          ///< tick records written
  std::uint64_t state_hash = 0;     ///< Simulation::state_hash() after the last step
  std::uint64_t dropped = 0;        ///< records lost to a full ring (0 in a replayable recording)
};

/// Names of StepRecord::timing_us, in order.
inline constexpr std::array<const char*, 7> kStepTimingNames = {
    "broad_phase", "narrow_phase", "response", "deformation", "projection", "step", "model"};

}  // namespace trocar
