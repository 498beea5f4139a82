#pragma once
/// Bleeding: blood leaving a wound, running down the tissue surfaces under gravity, pooling and
/// staining, stopped by coagulation or a clip (docs/electrosurgery.md, "Bleeding").
///
/// BloodFilm — blood as a thin film on one triangle surface. Each vertex holds a volume V_i
/// (m³) lumped over its area A_i (a third of each adjacent triangle's rest area): thickness
/// h_i = V_i / A_i. The film flows by lubrication theory: a film of thickness h on a slope s
/// (sine of the inclination) moves at the depth-averaged speed of a Nusselt film,
///
///   u = ρ g s h² / (3 μ),   flux per unit width q = u h = ρ g s h³ / (3 μ)
///
/// (Nusselt 1916; Oron, Davis & Bankoff, Rev Mod Phys 69:931, 1997, eq. 2.28 without surface
/// tension). Blood: ρ = 1060 kg/m³, μ = 3.5 mPa·s (whole blood at 37 °C and high shear, where it
/// is nearly Newtonian; Wesołowski & Młynarczak 2019 measured 1064 kg/m³ and 3.35 ± 0.36 mPa·s
/// in 30 healthy donors; textbooks give 3.5–5.5 mPa·s).
///
/// Discretisation: finite volumes on the vertex-centred dual mesh, one transfer per edge. The
/// flux across the dual face of edge ij is q times that face's width w_ij = ½ (cot α + cot β) L_ij
/// (the circumcentric dual; α, β the angles opposite the edge, at rest; clamped at 0 where the
/// mesh is not Delaunay, so no flux ever runs against the drop), with s = Δ_ij / ℓ_ij the drop
/// along the edge over its current length:
///
///   Q_ij = ρ g h_m³ w_ij Δ_ij / (3 μ ℓ_ij)   (upwind: h_m is the mobile film of the higher end)
///
/// For a linear height the cotangent weights' fluxes balance exactly (the cotangent Laplacian of
/// a linear function is 0), so a uniform film on a plane stays uniform. On an open border the
/// flux across the border's half-edges (the dual cell's part of the border) leaves the surface:
/// a film runs off the edge of a sheet at the rate it arrives, and not at all across a
/// horizontal or uphill border. That is the continuous form of "a border low point sheds".
///
/// The film below the residual thickness h_r (the wetting layer that stays behind and stains) does
/// not flow: h_m = max(0, h − h_r); the film above it slides on it as on the wall. A film thicker
/// than surface tension can hold behaves as a liquid body: above max_thickness (the capillary
/// scale, see FilmProperties) it drips where the surface faces down (its excess leaves into
/// dripped()), and where the surface faces up its free surface (raised by the excess) drives the
/// flow, so a dip fills and then spills over its rim instead of holding a column of any height at
/// one vertex. (A rule of "any vertex over the maximum sheds" would empty a puddle in a
/// face-up dip into the pool; and a border rule of "a border low point sheds" would drain every
/// border vertex of a level sheet, where nothing should move.)
///
/// Time stepping: explicit, upwind, conservative (a transfer leaves one vertex and arrives at the
/// other: volume never appears or vanishes), in substeps chosen so that no donor gives more than
/// a Courant fraction of its mobile film per substep (the kinematic wave of q ∝ h³ runs at
/// 3u: Courant–Friedrichs–Lewy), at most max_substeps per step; beyond that, or whenever a
/// vertex's outflow would exceed its mobile film, its outflows are scaled down proportionally.
/// A substep visits only the active set (the wet vertices and their neighbours, grown as the
/// film spreads), so its cost follows the wet region. No allocation after construction.
///
/// Saline: irrigation adds saline to the same film, which then carries a mixture. Each vertex also
/// holds the blood part B_i ≤ V_i of its fluid; every transfer (flow, run-off, drip, suction) takes
/// blood in the donor's proportion B/V, so blood and saline are each conserved. The mixture's
/// viscosity is interpolated linearly in the blood fraction between saline's and blood's (a
/// modelling choice: diluted blood thins towards its plasma-and-saline viscosity).
///
/// Stain: each vertex accumulates the thickness of blood that has arrived at it (by flow or from a
/// wound), D_i; its stain is 1 − exp(−D_i / stain_thickness): 0 where no blood came, near 1 where
/// much passed. Saline that arrives washes it: D_i ← D_i e^{−s / wash_thickness} for s (m) of
/// saline arriving, so a vertex under a steady mixture of blood fraction f settles at
/// D ≈ wash_thickness f / (1 − f): diluted blood stains less, irrigation cleans. Suction takes
/// fluid, not the stain.
///
/// Drips: what leaves the surface from a vertex (run-off across the open border, drips from an
/// overhang) is also kept per vertex as pending (pending_drips) until the owner lands it on a
/// surface below (Bleeding::land) or lets it go.
///
/// Bleeding — the wounds over several tissues' films: a cut vessel bleeds Q = v̄ π d² / 4 (v̄ the
/// mean blood speed of its kind) into its tissue's film at the wound's vertex until it is sealed
/// by coagulation (within the energy's sealing limit) or a clip. Invariants, to rounding:
///
///   emitted() = blood_volume() + pool_blood() + suctioned_blood()
///   emitted() + irrigated() = volume() + pool() + suctioned()
///
/// (Where what drips off one surface lands on another: drip_landing.h.)
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// The blood film's properties (the defaults are whole blood on peritoneum).
struct FilmProperties {
  Real density = 1060;     ///< ρ, kg/m³ (whole blood 1050–1065; Wesołowski & Młynarczak 2019: 1064)
  Real viscosity = 3.5e-3; ///< μ, Pa·s (whole blood at high shear, 37 °C: 3.35–4 mPa·s)
  /// h_r, m: the wetting layer a film leaves behind, which does not flow (a few red cells deep:
  /// an erythrocyte is about 2 µm thick and 8 µm across). A modelling choice; it sets how much
  /// blood a track keeps.
  Real residual_thickness = 2e-5;
  /// m: the thickness surface tension can hold. The capillary length of blood is
  /// √(γ / (ρ g)) = 2.2 mm (γ = 52 mN/m, Wesołowski & Młynarczak 2019); a large puddle stands
  /// 2 ℓ_c sin(θ/2) high (de Gennes, Brochard-Wyart & Quéré, "Capillarity and Wetting
  /// Phenomena", Springer 2004, ch. 2), 3.2 mm at θ = 90°. Under a surface facing down at cos φ
  /// to gravity a film drips beyond max_thickness / √cos φ (only the normal component of gravity
  /// pulls it off: the capillary length with g cos φ).
  Real max_thickness = 3e-3;
  /// m: the arrived thickness that stains a vertex to 1 − 1/e (a modelling choice: a film's
  /// passage of a few tens of µm darkens the tissue visibly).
  Real stain_thickness = 5e-5;
  /// Pa·s: saline's viscosity, for irrigation fluid (water at 37 °C: 0.69 mPa·s, CRC Handbook of
  /// Chemistry and Physics; 0.9 % NaCl adds about 2 %).
  Real saline_viscosity = 0.7e-3;
  /// m of saline arriving at a vertex that fades its stain's measure to 1/e (assumed: a tenth of a
  /// millimetre of irrigation passing rinses a stained patch visibly; under a steady mixture of
  /// blood fraction f the measure settles at wash_thickness f / (1 − f), so blood diluted 1:10
  /// stains to 1 − e^(−0.22) = 0.2 where whole blood stains fully).
  Real wash_thickness = 1e-4;
  /// Largest fraction of its mobile film a vertex gives per substep (Courant number of the
  /// kinematic wave is 3× this: 0.3 keeps the upwind scheme below 1).
  Real courant = 0.3;
  /// Substeps per step() at most; beyond, the proportional limit keeps it conservative but the
  /// film lags thin-film theory. Irrigation needs many: a 10 ml/s jet on a 20° slope runs as a
  /// film about 0.3 mm thick at over 1 m/s, which takes about 256 substeps per 1/30 s on 2 mm
  /// cells (with 32 it piled up 5 mm thick); each substep costs only the wet region.
  int max_substeps = 256;
};

/// The depth-averaged speed of a Nusselt film of thickness h (m) on a slope s (sine of the
/// inclination) under gravity g (m/s²): ρ g s h² / (3 μ), m/s.
Real nusselt_speed(const FilmProperties& p, Real gravity, Real slope, Real thickness);

/// Blood as a film on one triangle surface (see the file comment).
class BloodFilm {
 public:
  BloodFilm() = default;
  /// Builds the dual mesh (vertex areas, edges and their dual widths, the open border) from the
  /// rest state. Every vertex starts dry and unstained.
  BloodFilm(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions,
            const FilmProperties& properties = {});

  /// Adds `volume` (m³, ≥ 0) of blood at `vertex`. A vertex the surface does not have (or one of
  /// no area, which cannot hold a film) lets it drip: it goes to dripped() (not pending: it has no
  /// place). No allocation.
  void add(std::uint32_t vertex, Real volume) { add_mixture(vertex, volume, volume); }
  /// Adds `volume` (m³) of saline at `vertex` (irrigation), as add().
  void add_saline(std::uint32_t vertex, Real volume) { add_mixture(vertex, volume, 0); }
  /// Adds `volume` (m³) of fluid of which `blood` (0 ≤ blood ≤ volume) is blood, as add().
  void add_mixture(std::uint32_t vertex, Real volume, Real blood);

  /// Advances by dt with the tissue's current (deformed) vertex positions and gravity (m/s²):
  /// flow, run-off across open borders, drips from overhangs, stain. No allocation. Nothing flows
  /// with zero gravity; a dry surface costs one pass over its vertices.
  void step(std::span<const Vec3> positions, const Vec3& gravity, Real dt);

  /// Removes the film of every vertex within `radius` of `centre` (at `positions`), at most
  /// `max_volume` in all (proportionally, when there is more). Returns the volume removed (m³),
  /// its blood part in `*blood` when given. The stain stays. No allocation.
  Real remove_within(std::span<const Vec3> positions, const Vec3& centre, Real radius, Real max_volume,
                     Real* blood = nullptr);

  /// After a topology change (`rest_positions` and `vertex_origin` have one entry per new vertex,
  /// each origin an old vertex): new vertex v takes old vertex `vertex_origin[v]`'s film, arrived
  /// thickness and stain. When several new vertices share an origin (a vertex split by a cut),
  /// its film is split in proportion to their new areas, so the thickness is the same on each
  /// side and the volume is kept (equally where they have no area). The film of an old vertex no
  /// new vertex copies (removed with its tissue) falls off: it goes to dripped().
  void remap(std::span<const std::uint32_t> vertex_origin, std::span<const Triangle> triangles,
             std::span<const Vec3> rest_positions);

  std::size_t size() const { return film_.size(); }               ///< vertices
  std::span<const Real> film() const { return film_; }            ///< m³ of fluid per vertex
  std::span<const Real> blood() const { return blood_; }          ///< m³ of it that is blood
  std::span<const Real> area() const { return area_; }            ///< m² per vertex (lumped, rest)
  std::span<const Real> stain() const { return stain_; }          ///< 0…1 per vertex, monotone
  /// m of blood that has arrived at each vertex so far (the stain's measure), monotone.
  std::span<const Real> arrived() const { return arrived_; }
  Real thickness(std::size_t vertex) const;                       ///< m: film / area (0 without area)
  Real blood_thickness(std::size_t vertex) const;                 ///< m: blood / area (0 without area)
  Real volume() const;                                            ///< m³ of fluid on the surface
  Real blood_volume() const;                                      ///< m³ of blood on the surface
  Real dripped() const { return dripped_; }                       ///< m³ of fluid shed off so far
  Real dripped_blood() const { return dripped_blood_; }           ///< m³ of blood shed off so far
  /// Per vertex: fluid (m³) shed from it since the last clear_drips(), and its blood part; whether
  /// any is.
  std::span<const Real> pending_drips() const { return drip_; }
  std::span<const Real> pending_blood() const { return drip_blood_; }
  bool dripping() const { return dripping_; }
  void clear_drips();
  /// Any fluid on the surface (cheap: kept by every change).
  bool wet() const { return wet_; }
  /// Fluid has arrived on the surface at some time (it may show a film or a stain).
  bool touched() const { return touched_; }
  /// Substeps the last step() took (1 when nothing flowed).
  int last_substeps() const { return last_substeps_; }
  std::span<const Vec3> rest_positions() const { return rest_; }
  const FilmProperties& properties() const { return properties_; }

 private:
  void build(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions);
  void shed_overhangs();
  void update_stain();
  /// Takes `volume` of fluid (≤ film) from vertex i with its blood in proportion; returns the blood.
  Real take(std::size_t i, Real volume);
  /// Sheds `volume` of fluid with `blood` of it from vertex i off the surface (pending there).
  void shed(std::size_t i, Real volume, Real blood);
  /// Fluid arriving at vertex i: `blood` of it adds to the stain's measure, the rest washes it.
  void arrive(std::size_t i, Real volume, Real blood);
  /// Puts wet vertex i and its neighbours in the active set.
  void expand(std::uint32_t i);

  FilmProperties properties_;
  std::vector<Triangle> triangles_;
  std::vector<Vec3> rest_;
  std::vector<Real> area_;     ///< A_i, m²
  std::vector<Real> film_;     ///< V_i, m³ of fluid
  std::vector<Real> blood_;    ///< B_i ≤ V_i, m³ of blood
  std::vector<Real> drip_, drip_blood_;  ///< per vertex: shed since clear_drips(), m³
  std::vector<Real> arrived_;  ///< D_i, m
  std::vector<Real> stain_;    ///< 1 − exp(−D_i / stain_thickness)
  /// Each undirected edge of non-zero dual width once (a transfer is one subtraction and one
  /// addition: conservative).
  struct Edge {
    std::uint32_t a, b;
    Real width;  ///< w_ab = ½ (cot α + cot β) L_ab at rest, ≥ 0, m
  };
  std::vector<Edge> edges_;
  /// Open-border edges (used by one triangle) in their triangle's order a → b, c the third corner:
  /// the outward in-plane normal is (x_b − x_a) × n̂.
  struct BorderEdge {
    std::uint32_t a, b, c;
  };
  std::vector<BorderEdge> border_;
  // Scratch for step(), sized at build().
  std::vector<Real> depth_;         ///< ĝ · x_i, m (larger is lower)
  std::vector<Real> up_;            ///< max(0, −n̂_i · ĝ): how much the surface faces up
  std::vector<Real> down_;          ///< max(0, n̂_i · ĝ): how much it faces down
  std::vector<Vec3> normal_;        ///< area-weighted vertex normals (current)
  std::vector<Real> border_width_;  ///< Σ ½ (outward border normal · ĝ) |e|, clamped ≥ 0, m
  std::vector<Real> length_;        ///< current edge lengths ℓ, m
  /// Per vertex, its edges' indices (compressed rows: adjacency_offset_[i] … [i + 1]).
  std::vector<std::uint32_t> adjacency_offset_, adjacency_;
  /// The active set of a step: wet vertices (expanded_) and their neighbours, each once (in_set_).
  std::vector<std::uint32_t> active_;
  std::vector<std::uint8_t> in_set_, expanded_;
  /// One substep's transfers: donor, receiver, rate (m³/s), the levelling cap (m³).
  struct Transfer {
    std::uint32_t from, to;
    Real rate, cap;
  };
  std::vector<Transfer> moving_;
  std::vector<Real> out_;           ///< per vertex outflow, m³/s
  std::vector<Real> scale_;         ///< per vertex: the share of its outflow it gives this substep
  std::vector<Real> mobile_;        ///< per vertex: film above the residual layer, m³
  std::vector<Real> drive_;         ///< per vertex: k h_m³, m²/s
  std::vector<Real> surface_;       ///< per vertex: depth of the film's driving surface, m
  std::vector<Real> fraction_;      ///< per vertex: its blood fraction at the substep's start
  Real dripped_ = 0, dripped_blood_ = 0;
  bool dripping_ = false, wet_ = false, touched_ = false;
  int last_substeps_ = 1;
};

/// A wound's vessel.
struct VesselSpec {
  Real diameter = 1e-3;  ///< m
  bool artery = false;
};

/// The energy that coagulates the wound: what it can seal.
enum class EnergyModality : std::uint8_t {
  kMonopolar,  ///< the hook: seals vessels up to BleedingProperties::monopolar_limit
  kBipolar,    ///< bipolar vessel sealing: up to bipolar_limit
};

/// A wound's state.
enum class WoundState : std::uint8_t {
  kBleeding,   ///< open
  kNeedsClip,  ///< open, and energy was applied that cannot seal a vessel this wide: clip it
  kSealed,     ///< closed by coagulation
  kClipped,    ///< closed by a clip
};

/// Bleeding and haemostasis (scene key "bleeding").
struct BleedingProperties {
  /// m/s: the mean blood speed in a small artery (1–4 mm). Mean speed falls from about 0.2–0.3 m/s
  /// in the aorta (Guyton & Hall, Textbook of Medical Physiology: 33 cm/s) to about 1.5 cm/s in
  /// arterioles; the small muscular arteries surgery meets run at 0.1–0.2 m/s (Caro, Pedley,
  /// Schroter & Seed, "The Mechanics of the Circulation", 1978, after Burton).
  Real artery_speed = 0.15;
  /// m/s: the mean speed in a small vein: a few cm/s (venules 0.5 cm/s, venae cavae 8–15 cm/s,
  /// same sources).
  Real vein_speed = 0.03;
  /// m: the largest vessel each energy seals (Sankaranarayanan et al., "Common uses and cited
  /// complications of energy in surgery", Surg Endosc 27:3056, 2013: monopolar about 2 mm,
  /// bipolar vessel sealing up to 7 mm).
  Real monopolar_limit = 2e-3;
  Real bipolar_limit = 7e-3;
  /// The Arrhenius Ω at the wound that seals a vessel of `seal_reference_diameter` or less; a wider
  /// one needs seal_damage (d / d_ref)². The wall to seal is thicker in proportion to d (the
  /// wall-to-lumen ratio of a muscular artery is roughly constant), heat crosses it in a time
  /// ∝ thickness² (diffusion), and at a held surface temperature Ω grows in proportion to time.
  /// Ω = 1 is the usual coagulation threshold (Pearce, Int J Hyperthermia 29:262, 2013).
  Real seal_damage = 1.0;
  Real seal_reference_diameter = 1e-3;
  /// Wounds reserved at construction (open_wound beyond it may allocate, never step()).
  std::size_t wound_capacity = 64;
};

/// The mean blood speed in the vessel (m/s).
Real vessel_speed(const BleedingProperties& p, const VesselSpec& vessel);
/// The bleeding rate of a wound in `vessel` (m³/s): v̄ π d² / 4 (1 − σ)², σ the seal's progress
/// (0…1): coagulation shrinks the lumen (radius ∝ 1 − σ) before it closes it.
Real bleeding_rate(const BleedingProperties& p, const VesselSpec& vessel, Real seal_progress = 0);
/// The Ω that seals the vessel: seal_damage · max(1, (d / d_ref)²).
Real seal_threshold(const BleedingProperties& p, const VesselSpec& vessel);
/// The largest diameter `modality` seals (m).
Real seal_limit(const BleedingProperties& p, EnergyModality modality);

/// Wounds and haemostasis over several tissues' blood films.
class Bleeding {
 public:
  explicit Bleeding(const BleedingProperties& properties = {});

  /// Adds a tissue's surface (dry) and returns its index.
  std::size_t add_tissue(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions,
                         const FilmProperties& film = {});
  /// A topology change of tissue `tissue` (BloodFilm::remap). Each wound at an old vertex moves
  /// to the first new vertex that copies it (the one that keeps its place after a cut), or, when
  /// none does, to the new vertex nearest its old rest position; with no vertex left, its blood
  /// drips into the pool.
  void remap_tissue(std::size_t tissue, std::span<const std::uint32_t> vertex_origin,
                    std::span<const Triangle> triangles, std::span<const Vec3> rest_positions);

  /// Opens a wound in `vessel` at `vertex` of `tissue`, bleeding from `time` (s, this object's
  /// clock: the sum of step()'s dt), and returns its index.
  std::size_t open_wound(std::size_t tissue, std::uint32_t vertex, const VesselSpec& vessel, Real time);

  /// Advances by dt: every open wound adds its rate × the part of [time(), time() + dt] it was
  /// open into its film; then each film flows with `positions[tissue]` (an empty span, or none:
  /// that tissue's film does not move this step). No allocation.
  void step(std::span<const std::span<const Vec3>> positions, const Vec3& gravity, Real dt);

  /// Energy at the wound for dt, with `damage` the Arrhenius Ω of the tissue there. Within the
  /// modality's limit the lumen closes as Ω rises (bleeding_rate's σ = Ω / seal_threshold) and
  /// the wound is sealed, at time(), once Ω reaches the threshold; a wider vessel does not seal
  /// and reports kNeedsClip. Returns the wound's state.
  WoundState coagulate(std::size_t wound, Real damage, Real dt, EnergyModality modality = EnergyModality::kMonopolar);
  /// A clip: closes any wound at time() (a sealed one keeps its seal time).
  void clip(std::size_t wound);

  /// Suction at `tip` (m) within `radius` on tissue `tissue` at `positions`: removes fluid up to
  /// rate × dt (m³/s × s). Returns the volume removed. No allocation.
  Real suction(std::size_t tissue, std::span<const Vec3> positions, const Vec3& tip, Real radius, Real rate, Real dt);
  /// Irrigation: `volume` (m³) of saline onto tissue `tissue` at `vertex`. No allocation.
  void irrigate(std::size_t tissue, std::uint32_t vertex, Real volume);

  /// Seconds from the wound's opening to its closing; empty while it bleeds.
  std::optional<Real> time_to_haemostasis(std::size_t wound) const;
  WoundState state(std::size_t wound) const { return wounds_[wound].state; }
  /// The wound's current rate (m³/s; 0 once closed).
  Real rate(std::size_t wound) const;

  struct Wound {
    std::size_t tissue;
    std::uint32_t vertex;
    VesselSpec vessel;
    Real opened;       ///< s
    Real closed = 0;   ///< s, when state is kSealed or kClipped
    Real damage = 0;   ///< the highest Ω applied by an energy that can seal it
    Real energy_time = 0;  ///< s of energy applied at the wound
    Real emitted = 0;  ///< m³ it has bled
    WoundState state = WoundState::kBleeding;
  };
  std::span<const Wound> wounds() const { return wounds_; }
  std::size_t tissues() const { return films_.size(); }
  const BloodFilm& film(std::size_t tissue) const { return films_[tissue]; }

  Real time() const { return time_; }
  Real emitted() const { return emitted_; }      ///< m³ bled by all wounds
  Real irrigated() const { return irrigated_; }  ///< m³ of saline irrigated
  Real volume() const;                           ///< m³ of fluid on all surfaces
  Real blood_volume() const;                     ///< m³ of blood on all surfaces
  Real pool() const;                             ///< m³ of fluid dripped off all surfaces
  Real pool_blood() const;                       ///< m³ of blood dripped off all surfaces
  Real suctioned() const { return suctioned_; }  ///< m³ of fluid removed by suction
  Real suctioned_blood() const { return suctioned_blood_; }  ///< m³ of blood removed by suction
  const BleedingProperties& properties() const { return properties_; }

 private:
  BleedingProperties properties_;
  std::vector<BloodFilm> films_;
  std::vector<Wound> wounds_;
  Real time_ = 0;
  Real emitted_ = 0;
  Real irrigated_ = 0;
  Real suctioned_ = 0, suctioned_blood_ = 0;
};

}  // namespace trocar
