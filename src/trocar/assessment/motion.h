#pragma once
/// Motion metrics of one instrument's tip (docs/assessment.md, "Motion"). Samples at a fixed
/// interval dt; every function is deterministic (a fixed summation order) and takes no clock.
#include <cstdint>
#include <span>

#include "trocar/core/types.h"

namespace trocar {

/// Σ |p[k+1] − p[k]| over samples k where both are present (m).
Real path_length(std::span<const Vec3> tip, std::span<const std::uint8_t> present = {});

/// Depth perception: Σ |(p[k+1] − p[k]) · a[k]|, the path along the shaft's axis (m): in and out
/// through the port, the motion a surgeon who misjudges depth makes in excess.
Real depth_path(std::span<const Vec3> tip, std::span<const Vec3> axis, std::span<const std::uint8_t> present = {});

/// Tip speed per sample (m/s): central differences inside, one-sided at the ends; 0 where not
/// present.
void tip_speeds(std::span<const Vec3> tip, Real dt, std::span<Real> speed, std::span<const std::uint8_t> present = {});

/// Time (s) with the tip slower than `threshold` (m/s) while present: dt per such sample.
Real idle_time(std::span<const Real> speed, Real dt, Real threshold, std::span<const std::uint8_t> present = {});

/// Log dimensionless jerk of a movement (Balasubramanian, Melendez-Calderon & Burdet 2012,
/// IEEE TBME 59:2126; Sensors 23:3146 for surgical motion): LDLJ = −ln( T³/v_peak² ·
/// ∫₀ᵀ |d²v/dt²|² dt ), v the tip's velocity vector, T the movement's duration, the second
/// derivative by central differences, the integral by the trapezoid rule. Higher (closer to 0)
/// is smoother: −5.32 for a minimum-jerk reach (720/3.516 = 204.8), lower for a hesitant one.
/// `stride` subsamples first (≥ 1): jerk of 1 ms samples is dominated by the step's noise.
/// Returns 0 for fewer than 6 samples or no motion.
Real log_dimensionless_jerk(std::span<const Vec3> tip, Real dt, std::size_t stride = 1);

/// Share of the samples (as time, s) where present and not in view.
Real out_of_view_time(std::span<const std::uint8_t> present, std::span<const std::uint8_t> in_view, Real dt);

}  // namespace trocar
