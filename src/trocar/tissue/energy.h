#pragma once
/// The elastic energy of a tissue state, measured every simulation step (docs/scene.md "What a step
/// measures"): the same value as potential_energy() without gravity, computed with the integrators'
/// padded AVX2 passes (springs four at a time, one triangle pass for the volume) instead of the
/// scalar reference. On the shared liver this is the larger part of a step's metrics.
#include <span>

#include "trocar/core/types.h"
#include "trocar/tissue/explicit_kernels.h"
#include "trocar/tissue/settings.h"

namespace trocar {

/// Measures elastic energy for one tissue; sized once, no allocation per call.
class ElasticEnergyMeter {
 public:
  /// A meter for `settings` (kept by reference: it must outlive the meter).
  explicit ElasticEnergyMeter(const MassSpringSettings& settings);

  /// Springs, area, volume and home springs at positions x (J); potential_energy(x) with
  /// gravity off, to rounding.
  Real elastic(std::span<const Vec3> x);

  /// The settings' springs `springs` changed stiffness, rest length or damping: copies them
  /// again, in place. No allocation.
  void springs_changed(std::span<const std::uint32_t> springs);

  /// Runs the portable passes even where the CPU has AVX2 (for tests and comparisons).
  void set_simd(bool on) { use_avx2_ = on && cpu_has_avx2_fma(); }

 private:
  const MassSpringSettings& settings_;
  tissue_detail::SpringLayout springs_;
  tissue_detail::PaddedArrays arrays_;
  std::span<tissue_detail::Padded3> x_;
  bool use_avx2_ = false;
};

}  // namespace trocar
