#pragma once
/// Heat and thermal damage of a tissue's surface under an electrode (docs/electrosurgery.md).
///
/// Each triangle is a lumped slab of its rest area A and the heated depth d (mass m = ρ A d,
/// heat capacity C = m c). Per step, with the power P an electrode puts into it:
///
///   C dT/dt = P + Σ_j G_ij (T_j − T_i) − C β (T − T_b)        (Pennes 1948, lumped)
///
/// G_ij = κ d ℓ_ij / s_ij conducts to the triangles across its edges (ℓ the shared edge, s the
/// distance between the centroids), β = w_b c_b / (ρ c) is perfusion. At 100 °C the tissue water
/// boils: the temperature holds and the heat goes into vaporising it, φ += Q / (m w L); a
/// triangle whose water is gone (φ ≥ 1) is cut (electrosurgical cutting is vaporisation:
/// Massarweh et al., J Am Coll Surg 202:520, 2006). Cell death is the Arrhenius damage integral
///
///   Ω(t) = ∫ A exp(−E_a / (R T(τ))) dτ                          (Henriques & Moritz 1947)
///
/// (Ω = 1: 63 % of the cells dead, the usual coagulation threshold; Pearce, Int J Hyperthermia
/// 29:262, 2013), integrated per step by Simpson's rule over the step's linear T(t).
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// Thermal properties of one tissue (scene key "thermal"; the defaults are soft tissue).
struct ThermalProperties {
  Real density = 1050;            ///< ρ, kg/m³ (IT'IS tissue database, soft tissue ≈ 1050)
  Real specific_heat = 3600;      ///< c, J/(kg·K) (IT'IS: 3400–3700 for muscle, liver, peritoneum)
  Real conductivity = 0.5;        ///< κ, W/(m·K) (IT'IS: 0.46–0.52)
  /// d, m: the layer under the electrode the power heats (about the thermal spread of a hook, and
  /// the peritoneum with the fascia under it).
  Real heated_depth = 5e-4;
  Real water_fraction = 0.7;      ///< w (soft tissue 70–80 % water)
  Real latent_heat = 2.26e6;      ///< L, J/kg: water's heat of vaporisation at 100 °C
  Real perfusion = 0.5;           ///< w_b, kg/(m³·s): blood perfusion rate (Pennes)
  Real blood_specific_heat = 3617;  ///< c_b, J/(kg·K)
  Real body_temperature = 310.15;   ///< T_b, K (37 °C)
  Real boiling_temperature = 373.15;  ///< K (100 °C): water boils, the temperature holds
  Real arrhenius_rate = 3.1e98;     ///< A, 1/s (Henriques & Moritz 1947)
  Real activation_energy = 6.28e5;  ///< E_a, J/mol (Henriques & Moritz 1947)
};

/// The universal gas constant, J/(mol·K).
inline constexpr Real kGasConstant = 8.314462618;

/// The Arrhenius damage rate A exp(−E_a / (R T)) at temperature T (K), 1/s.
Real damage_rate(const ThermalProperties& p, Real temperature);

/// The thermal state of a tissue's triangles and how it advances.
class ThermalField {
 public:
  ThermalField() = default;
  /// `rest_areas` per triangle (m²), `triangles` (vertex triplets) and `rest_positions` for the
  /// conduction between neighbours. Every triangle starts at body temperature, undamaged.
  ThermalField(const ThermalProperties& properties, std::span<const Triangle> triangles,
               std::span<const Vec3> rest_positions, std::span<const Real> rest_areas);

  /// Advances by dt with `power` per triangle (W, one per triangle; empty: none). No allocation;
  /// nothing to do (and no cost beyond reading `power`) while no triangle is hot.
  void step(std::span<const Real> power, Real dt);

  /// Puts `joules` of heat into triangle t at once (a dose without an electrode: scripted burns,
  /// tests): it warms to the boiling point, and the rest boils its water off. Counted as delivered.
  void add_heat(std::size_t t, Real joules);
  /// Marks triangle t cut (its water gone, φ = 1) without heat: a cut by other means.
  void vaporise(std::size_t t) { vaporised_[t] = std::max<Real>(vaporised_[t], 1); }

  /// Keeps the state of the triangles that remain after a topology change: new triangle k takes
  /// old triangle origin[k]'s state. When `origin` is one-to-one (a cut: kept triangles keep
  /// their rest shape, and two that shared an edge still share it, a vertex being split only
  /// between fans), the conduction links are the old ones between kept triangles, renumbered (no
  /// edge table: the same links, in the same order, as a rebuild); otherwise they are rebuilt.
  void remap(std::span<const std::uint32_t> origin, std::span<const Triangle> triangles,
             std::span<const Vec3> rest_positions, std::span<const Real> rest_areas);

  std::size_t size() const { return temperature_.size(); }              ///< triangles
  std::span<const Real> temperature() const { return temperature_; }    ///< K per triangle
  std::span<const Real> damage() const { return damage_; }              ///< Ω per triangle
  std::span<const Real> vaporised() const { return vaporised_; }        ///< φ per triangle (0…1)
  /// Coagulated: Ω ≥ 1. Returns whether triangle t is.
  bool coagulated(std::size_t t) const { return damage_[t] >= 1; }
  /// Cut: its water gone, φ ≥ 1.
  bool cut(std::size_t t) const { return vaporised_[t] >= 1; }
  /// True while any triangle is warmer than the body by more than 0.01 K (step() has work).
  bool hot() const { return hot_; }
  /// Energy delivered so far (J) and where it went (J): stored as heat above T_b, latent in the
  /// vapour, carried off by perfusion. delivered = stored + latent + perfused (to rounding).
  Real delivered() const { return delivered_; }
  Real stored() const;
  Real latent() const;
  Real perfused() const { return perfused_; }
  const ThermalProperties& properties() const { return properties_; }

 private:
  /// Heat capacities and vapour energies from the rest areas, and the conduction links.
  void build(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions,
             std::span<const Real> rest_areas);
  void build_conduction(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions);
  /// Heat capacities and vapour energies from the rest areas.
  void build_capacity(std::span<const Real> rest_areas);
  /// The largest ΣG/C (the explicit conduction's stability bound) from links_ and capacity_.
  void update_max_rate();

  ThermalProperties properties_;
  std::vector<Real> capacity_;     ///< C per triangle, J/K
  std::vector<Real> temperature_;  ///< K
  std::vector<Real> damage_;       ///< Ω
  std::vector<Real> vaporised_;    ///< φ
  std::vector<Real> vapour_energy_;  ///< J per triangle to vaporise all its water, m w L
  /// Conduction links between edge neighbours: (a, b, G).
  struct Link {
    std::uint32_t a, b;
    Real conductance;  ///< W/K
  };
  std::vector<Link> links_;
  std::vector<Real> heat_;         ///< scratch: J per triangle this substep
  /// max_t Σ_j G_tj / C_t (1/s): step() splits dt into substeps of at most 0.5 / max_rate_ so
  /// that the explicit conduction stays stable on slivers.
  Real max_rate_ = 0;
  bool hot_ = false;
  Real delivered_ = 0, perfused_ = 0;
};

}  // namespace trocar
