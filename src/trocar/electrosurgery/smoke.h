#pragma once
/// Surgical smoke from electrosurgery (docs/electrosurgery.md, "Smoke").
///
/// Cutting with a monopolar hook boils the tissue's water off (thermal.h); the vapour carries
/// aerosolised tissue with it and condenses into a visible plume that rises from the burn,
/// spreads, veils the laparoscope's view and clears over seconds (Ulmer, AORN J 87:721, 2008;
/// Barrett & Garber, Surg Endosc 17:979, 2003). Opening a port's stopcock (venting) or a suction
/// instrument clears it faster. This is the simulation side: a fixed pool of puffs that the
/// renderer draws as soft lit sprites.
///
/// Each particle is a puff of radius r and centre opacity α (the sprite's alpha at its centre).
/// Per step of dt, with every coefficient computed once per step (the same for all particles):
///
///   lift:     a ← a e^{−dt/τ_b}                      (the puff's buoyancy, lost as it cools)
///   velocity: v ← v e^{−dt/τ_d} + β(dt) a             (drag toward the still gas, exactly)
///   position: x ← x + δ(dt) v + ε(dt) a + σ ξ        (ξ ~ N(0, 1) per axis, σ = √(2 D dt))
///   radius:   r ← min(r + g dt, r_max)
///   opacity:  α ← α e^{−(ln 2 / t½ + [venting] / τ_v) dt} (r_old / r_new)²
///
/// (β, δ, ε: the integrals of the linear ODEs over the step, smoke.cpp). The velocity is
/// integrated exactly rather than semi-implicitly: the ODE is linear, so the exact factor costs
/// nothing per particle, is stable for any dt, and makes the plume the same whether it is stepped
/// with the physics (1 ms) or with the frames (16 ms); semi-implicit Euler's (1 + dt/τ)^−n is off
/// by t dt / (2 τ²) (3 % at 16 ms, τ = 0.5 s, t = 1 s).
///
/// The opacity's (r_old/r_new)² is dilution: a puff that expands spreads the same aerosol over a
/// larger cross-section, so α r² (how much light it blocks in all) is kept as it grows, and only
/// fading, venting and suction take it away. Without it a growing puff would block more light as
/// it aged and the smoke would thicken while it spreads.
///
/// Deterministic: the field has its own generator (splitmix64) and draws its Gaussians from
/// integer arithmetic only (smoke.cpp: the sum of four uniforms, not Box–Muller, whose log and cos
/// are not correctly rounded and may differ in the last bit between C libraries). The same seed
/// and the same calls give the same bits; across C libraries the only libm calls are the step's
/// few exp/expm1/log factors (once per step, not per particle).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// The smoke's parameters (scene key "smoke"). Figures marked "tuned" have no measurement behind
/// them: they were chosen for the look and the time scales surgeons describe.
struct SmokeSettings {
  /// Most particles alive at once. 4096 puffs step in tens of µs (bench_electrosurgery) and the
  /// renderer draws them as one instanced batch; a 40 W cut fills it in about 1.4 s, after which
  /// the faintest puffs (in still air: the oldest) make room.
  std::size_t capacity = 4096;

  /// Particles per joule of vaporisation energy (the heat that boiled water off this step: the
  /// latent share of ThermalField's energy). 1 J boils 0.44 mg of water (L = 2.26 MJ/kg), about
  /// 0.75 mL of vapour at 100 °C. Tuned together with `birth_opacity` and `birth_radius`: with
  /// 100 /J, α₀ = 0.08 and r₀ = 3 mm, one joule makes 100 · α₀ π r₀² = 2.3 cm² of full-opacity
  /// cover, so a 1 s cut at 40 W (about 30 J into vapour once the tissue boils) spread over the
  /// 10 × 10 cm that a scope sees 7 cm away veils it to an optical depth about 0.5: hazy but not
  /// white, as a few seconds of hook work look. A few hundred per joule would fill 4096 particles
  /// in under a second and cut the plume's tail off.
  Real particles_per_joule = 100;

  /// m/s: the puff's initial speed along `up`. Tuned (a few cm/s, the drift of condensed smoke in
  /// laparoscopic video); the vapour itself leaves the burn faster, but it condenses within
  /// millimetres and the aerosol that is seen is carried by the weakly buoyant gas around it.
  Real rise_speed = 0.05;
  /// s: τ_b, the time constant of the lift's decay as the puff mixes with the CO₂ and cools
  /// (tuned). The lift starts at rise_speed / drag_time, so that a hot puff keeps its rise speed
  /// (the terminal velocity of that lift against the drag); a puff born at rest in still gas
  /// then rises rise_speed · (drag_time + buoyancy_time) = 5 cm in all, and lingers there.
  /// 0: no buoyancy.
  Real buoyancy_time = 0.5;
  /// s: τ_d, the time constant of the drag that slows a puff to the still gas around it (tuned:
  /// a puff a few mm across in CO₂ follows the gas within a fraction of a second).
  /// Infinity: no drag.
  Real drag_time = 0.5;
  /// m²/s: D, the turbulent spread of the puffs (a random walk of σ = √(2 D dt) per axis). Water
  /// vapour's molecular diffusivity in CO₂ is about 1.6e-5 m²/s (Cussler, Diffusion, 3rd ed.,
  /// table 5.1-2) and the aerosol's Brownian diffusivity is far smaller; what spreads the smoke
  /// in the abdomen is stirring by the insufflator's inflow and the instruments. Tuned: 5e-5 m²/s
  /// spreads a plume σ = 2 cm in 4 s, across the scope's view in several seconds.
  Real diffusion = 5e-5;
  /// m: standard deviation per axis of a particle's birth position around the burn (tuned: the
  /// hook's foot is 1–2 mm wide).
  Real position_jitter = 1e-3;
  /// m/s: standard deviation per axis of a particle's birth velocity (tuned).
  Real velocity_jitter = 0.01;

  /// m: the puff's radius at birth (the hook's foot and the burn, a few mm).
  Real birth_radius = 3e-3;
  /// m/s: how fast a puff expands (tuned; a turbulent plume widens 0.1–0.15 of its rise, Morton,
  /// Taylor & Turner, Proc R Soc A 234:1, 1956, which at a few cm/s is a few mm/s). The opacity
  /// dilutes as it grows (α r² kept).
  Real growth_rate = 3e-3;
  /// m: the largest a puff grows (tuned: beyond it a puff is part of the haze; a sprite much
  /// larger than a cm would blur the plume's shape).
  Real max_radius = 0.012;

  /// The sprite's alpha at its centre at birth (tuned with particles_per_joule).
  Real birth_opacity = 0.08;
  /// s: half-life of the opacity in still air (venting off): deposition on the wet peritoneum and
  /// the insufflator's slow exchange. Tuned: smoke in a closed, insufflated abdomen lingers for
  /// several seconds, up to tens of seconds for a thick plume.
  Real fade_half_life = 5.0;
  /// s: τ_v, with venting on every particle's opacity also decays as e^{−t/τ_v}. Tuned: the view
  /// clears within a few seconds of opening a port's stopcock; the well-mixed estimate for the
  /// whole cavity, V/Q = 3 L at an insufflator's 40 L/min, is 4.5 s, and the plume near the
  /// tissue the scope looks at, which the outflow draws first, clears faster.
  Real venting_time = 2.0;
  /// s: τ_s, within a suction tip's radius the opacity decays as e^{−t/τ_s}. A 2 cm sphere
  /// (34 mL) drawn at 20 L/min (333 mL/s, a suction cannula's flow; medical suction's high-flow
  /// class is ≥ 20 L/min, ISO 10079) empties in V/Q = 0.1 s.
  Real suction_time = 0.1;
  /// A particle whose opacity falls below this is removed (a quarter of an 8-bit alpha step: one
  /// such sprite changes no pixel, and even a hundred overlapping add only 0.1).
  Real min_opacity = 1e-3;
};

/// One puff of smoke.
struct SmokeParticle {
  Vec3 position;  ///< m, world
  Vec3 velocity;  ///< m/s
  Vec3 lift;      ///< m/s²: the buoyant acceleration (along the emitter's `up`), decaying
  Real age;       ///< s since birth
  Real radius;    ///< m: the sprite's radius
  Real opacity;   ///< the sprite's alpha at its centre (0…1)
};

/// A plume of smoke: a fixed pool of particles.
class SmokeField {
 public:
  /// Allocates the pool (settings.capacity particles) and its scratch once; nothing allocates
  /// after this. Throws std::invalid_argument for settings that cannot work (capacity 0,
  /// negative or non-finite rates, times ≤ 0 other than the documented "off" values).
  explicit SmokeField(const SmokeSettings& settings, std::uint64_t seed);

  /// Emits round(energy_joules · particles_per_joule) particles at `at`, the fractional
  /// remainder carried to the next call (so many small emissions give the count of one big one,
  /// to one particle). `up` is the unit direction against gravity. Each particle is born at
  /// `at` + N(0, position_jitter²) per axis with velocity rise_speed · up + N(0, velocity_jitter²),
  /// lift rise_speed / drag_time · up, birth radius and opacity, at the end of the pool. When the
  /// pool is full, the newcomers replace the faintest particles (ties: the older) in their slots,
  /// in slot order; more than `capacity` in one call keeps the last `capacity` of them. Energy
  /// ≤ 0 or non-finite emits nothing. No allocation.
  void emit(const Vec3& at, const Vec3& up, Real energy_joules);

  /// Advances every particle by dt (s; ≤ 0 does nothing) and removes those whose opacity fell
  /// below min_opacity, keeping the others in their order (compacted in place). No allocation.
  void step(Real dt);

  /// Venting (a port's stopcock open, or an evacuator running): every particle's opacity also
  /// decays with venting_time.
  void set_venting(bool on) { venting_ = on; }
  bool venting() const { return venting_; }

  /// A suction tip drawing for dt: the opacity of every particle whose centre is within `radius`
  /// (m) of `tip` decays by e^{−dt/suction_time}; those that fall below min_opacity are removed
  /// (the others keep their order). Particles outside are untouched. No allocation.
  void suction(const Vec3& tip, Real radius, Real dt);

  /// The live particles: in birth order until the pool has been full, then in the deterministic
  /// order of emit's replacement in place (sort them by depth to draw them).
  std::span<const SmokeParticle> particles() const { return {pool_.data(), size_}; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return pool_.size(); }
  /// Particles emitted so far (also those replaced or removed since).
  std::size_t emitted() const { return emitted_; }

  /// How much the smoke veils the segment from → to: Σ_i α_i ℓ_i / (2 r_i), ℓ_i the length of
  /// the segment inside particle i's sphere. A line through a puff's centre adds its opacity.
  /// For small opacities the sprites' alpha blending lets through Π(1 − α) ≈ e^{−τ} of the light,
  /// so τ reads as an optical depth (τ = 1: about a third of the view's light comes through).
  Real optical_depth(const Vec3& from, const Vec3& to) const;

  /// Σ α r² over the particles (π times it: m² of full-opacity cover), what the smoke blocks in
  /// all: growth keeps it, fading, venting and suction take it away.
  Real total_cover() const;

  const SmokeSettings& settings() const { return settings_; }

 private:
  /// Removes the particles with opacity < min_opacity, keeping the order.
  void remove_faint();
  /// Puts the slots of the `count` faintest particles (ties: the older, then the lower slot;
  /// count < size_) in ascending order in scratch_[0, count).
  void make_room(std::size_t count);
  /// A standard normal deviate from the field's generator.
  Real gaussian();

  SmokeSettings settings_;
  std::vector<SmokeParticle> pool_;     ///< capacity slots; the first size_ are live
  std::vector<std::uint32_t> scratch_;  ///< capacity indices: choosing whom to replace
  std::size_t size_ = 0;
  std::size_t emitted_ = 0;
  Real carry_ = 0.5;  ///< the fractional particle carried between emissions (0.5: rounding)
  std::uint64_t rng_;
  bool venting_ = false;
};

}  // namespace trocar
