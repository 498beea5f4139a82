#pragma once
/// Multirate fidelity (docs/runtime.md, "Multirate fidelity"): the force the haptic loop renders
/// at 1 kHz with physics at its own rate, against a lock-step reference at the same device poses: RMS error relative to the peak
/// force, and the largest force jump per tick when a new model arrives.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// What a comparison found.
struct FidelityResult {
  std::uint64_t ticks = 0;             ///< ticks compared
  double peak_force = 0;               ///< largest |F| of the reference (N)
  double rms_error = 0;                ///< RMS of |F − F_ref| over the ticks (N)
  double rms_fraction = 0;             ///< rms_error / peak_force
  double max_arrival_jump = 0;         ///< largest |F_k − F_{k−1}| at a tick where a new model arrived (N)
  double max_jump = 0;                 ///< largest |F_k − F_{k−1}| at any tick (N)
  double reference_max_jump = 0;       ///< the same of the lock-step reference (N): physics' own jumps
  double device_max_force = 0;         ///< the device's maximum (N)
  double physics_rate_hz = 0;          ///< physics steps per second of the multirate run
  /// Threads only: RMS difference of the two runs' *physics* forces (the step each tick's model
  /// came from vs the reference's step), relative to the peak: how far the simulations
  /// themselves went apart (the multirate physics samples the device at its own instants; after
  /// a slip the two diverge). 0 for the emulation, whose physics inputs are the reference's.
  double physics_rms_fraction = 0;
  std::uint64_t model_arrivals = 0;    ///< ticks at which a new model arrived
};

/// Force series of the two runs (per tick, instrument 0) → the figures.
FidelityResult compare_forces(const std::vector<Vec3>& rendered, const std::vector<Vec3>& reference,
                              const std::vector<std::uint8_t>& arrivals, double device_max_force);

/// Deterministic emulation (no threads, virtual clock): haptic ticks at rate_hz; physics steps
/// every `physics_every` ticks by physics_every/rate_hz seconds, and its model reaches the haptic
/// loop `latency_ticks` ticks later. The reference runs physics in lock-step (every tick, dt =
/// one period) on the same device poses. Instrument 0 is compared.
struct EmulationOptions {
  double rate_hz = 1000;
  int physics_every = 1;
  int latency_ticks = 1;
  double duration = 1.0;  ///< s
};
FidelityResult emulate_multirate(const std::string& scene_text, const std::filesystem::path& scene_dir,
                                 const EmulationOptions& options);

/// The real thing: the scene runs multirate on the runtime's threads for `duration` s of wall
/// time, recorded; then the lock-step reference runs on the recorded device poses tick by tick.
FidelityResult measure_multirate(const std::filesystem::path& scene, double duration, double rate_hz,
                                 const std::filesystem::path& recording);

}  // namespace trocar
