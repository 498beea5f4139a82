#pragma once
/// The one definition of a stable simulation state, used by `trocar run`, the studies, the
/// real-time report and the tests (docs/stability.md gives the reasoning and the figures).
///
/// A state is stable when every tissue position and velocity is finite and the tissues' kinetic
/// energy stays within what the scene's own mass can hold at a bounded speed:
///     E_kin ≤ ½ · M · v_bound²,   M = Σ tissue vertex masses, v_bound = kStableSpeedBound,
/// i.e. the tissues' mass-weighted RMS speed is at most v_bound. No tissue in a laparoscopic scene
/// moves at that speed (instruments move at ≤ 2 m/s); an integrator that diverges grows its
/// energy geometrically and passes the bound within a few steps.

namespace trocar {

/// The RMS tissue speed (m/s) above which a state counts as unstable: five times the fastest
/// instrument motion of the studies (2 m/s, the robustness suite's fastest poke).
inline constexpr double kStableSpeedBound = 10.0;

/// The largest kinetic energy (J) of a stable state of tissues of total mass `tissue_mass` (kg).
constexpr double stable_energy_bound(double tissue_mass) {
  return 0.5 * tissue_mass * kStableSpeedBound * kStableSpeedBound;
}

/// True for a finite state whose kinetic energy (J) is within stable_energy_bound(tissue_mass).
/// A non-finite energy fails both ways (NaN compares false).
constexpr bool is_stable(bool finite, double kinetic_energy, double tissue_mass) {
  return finite && kinetic_energy <= stable_energy_bound(tissue_mass);
}
/// The same, and every tissue's own mass-weighted RMS speed (the largest, `tissue_rms_speed`, m/s)
/// within kStableSpeedBound: the prosthetic mesh (0.65 g of a 4 kg groin) flung at 40 m/s holds
/// 0.5 J, far under the scene's bound of 200 J (docs/stability.md).
constexpr bool is_stable(bool finite, double kinetic_energy, double tissue_mass, double tissue_rms_speed) {
  return is_stable(finite, kinetic_energy, tissue_mass) && tissue_rms_speed <= kStableSpeedBound;
}

}  // namespace trocar
