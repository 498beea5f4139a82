#pragma once
/// What electrosurgery and bleeding look like, on the render side (docs/electrosurgery.md, "What
/// is drawn"). The physics step keeps only the bookkeeping — each triangle's burn, each wound's
/// emitted volume, each electrode's vaporisation energy (ViewSnapshot) — and the renderer runs
/// what is only seen: the blood flowing over the bleeding tissues (a BloodFilm per tissue) and
/// the smoke (a SmokeField). EffectsView holds that state between frames. It needs no GL context,
/// so the tests check its bookkeeping directly.
///
/// Per frame (update): the frame's simulated dt is the snapshot's time minus the last one's; a
/// jump back in time (a reset, a replay restarted) clears everything. Each wound feeds the film of
/// its tissue with its increase in emitted volume since the last frame, at its vertex; an open
/// irrigation valve (InstrumentView::irrigation) jets saline onto the first surface ahead of the
/// tip; the films (one per tissue, made when the first fluid arrives) flow with the snapshot's
/// positions and the scene's gravity; what drips or runs off a surface lands on the first surface
/// below it (DripLanding) or falls out of sight into the pool; an open suction valve draws fluid
/// within its radius of the tip, and smoke within its smoke radius. Each electrode's vapour
/// source emits smoke for the increase of its energy at its `at`, `up`, and the smoke steps by dt.
///
/// Conservation, by construction, to rounding:
///   fed() = blood_volume() + pool_blood() + suctioned_blood()
///   fed() + irrigated() = volume() + pool() + suctioned()
/// (lost() — blood of a wound on a tissue the renderer has no model of — is in the pool.)
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/electrosurgery/bleeding.h"
#include "trocar/electrosurgery/drip_landing.h"
#include "trocar/electrosurgery/smoke.h"
#include "trocar/sim/view_snapshot.h"

namespace trocar {

/// A tissue's model as the renderer draws it: its version (TissueBody::model_version), triangles
/// and rest positions (m).
struct TissueModel {
  std::uint32_t version = 0;
  std::vector<Triangle> triangles;
  std::vector<Vec3> rest;
};

/// For each vertex of `now`, the vertex of `before` at the same rest position (a cut copies rest
/// positions exactly; several new vertices may share one old one), else the nearest one. Empty
/// when `before` is empty.
std::vector<std::uint32_t> match_rest_positions(std::span<const Vec3> before, std::span<const Vec3> now);

/// What drives the effects this frame (RenderOptions' switches).
struct EffectsSwitches {
  bool blood = true;     ///< feed and flow the blood
  bool smoke = true;     ///< emit and step the smoke
  bool venting = false;  ///< SmokeField::set_venting
};

/// The render-side state of burns, blood and smoke (see the file comment).
class EffectsView {
 public:
  /// `gravity`: per tissue (m/s²; a zero entry takes (0, 0, −9.81)).
  explicit EffectsView(std::vector<Vec3> gravity = {}, const SmokeSettings& smoke = {},
                       const FilmProperties& film = {}, std::uint64_t seed = 0x5eed5a0c);

  /// Brings the blood and smoke up to `snap`, tissue t's current model being `models[t]`. A
  /// switch that is off leaves that part as it is (the wounds' and electrodes' increases are
  /// still counted for smoke, so switching it on does not emit a burst; the blood is fed what it
  /// missed when switched on). Returns the frame's dt (s; 0 on the first frame and after a reset).
  Real update(const ViewSnapshot& snap, std::span<const TissueModel> models, const EffectsSwitches& on);

  /// Forgets everything: films, smoke, what was fed and emitted, the clock.
  void clear();

  /// Writes tissue t's 4 floats per vertex for `vertex_count` vertices into `out`: coagulation and
  /// charring from the snapshot, blood film (the blood's thickness / 0.5 mm, clamped to 1: how red
  /// a film looks goes with the blood in it, Beer–Lambert, so diluted blood is paler and saline
  /// alone clear) and stain from its film. Returns false (and leaves `out` alone) when the tissue has no effect at all: it is then
  /// drawn as if nothing had happened to it, by the default program.
  bool fill(const ViewSnapshot& snap, std::size_t t, std::size_t vertex_count, bool blood, std::vector<float>& out) const;

  /// Tissue t's film, or null before the first fluid arrived (then every tissue has one).
  const BloodFilm* film(std::size_t t) const;
  /// The smoke, or null before any electrode boiled tissue.
  const SmokeField* smoke() const { return smoke_.get(); }

  Real fed() const { return fed_; }   ///< m³ of blood the wounds have fed (lost() included)
  Real irrigated() const { return irrigated_; }  ///< m³ of saline jetted
  Real volume() const;               ///< m³ of fluid on the films now
  Real blood_volume() const;         ///< m³ of blood on the films now
  Real pool() const;                 ///< m³ of fluid fallen off every surface, lost() included
  Real pool_blood() const;           ///< m³ of blood of it
  Real suctioned() const { return suctioned_; }  ///< m³ of fluid drawn in by suction
  Real suctioned_blood() const { return suctioned_blood_; }  ///< m³ of blood of it
  Real lost() const { return lost_; }  ///< m³ of wounds on tissues without a model
  /// The blood film's thickness drawn as 1 (m).
  static constexpr Real kFullFilm = 5e-4;

 private:
  /// Makes every tissue's film (dry) when the first fluid arrives: any surface may receive drips.
  void ensure_films(std::span<const TissueModel> models);
  /// Saline from every open irrigation valve onto the first surface ahead of its tip, for dt.
  void irrigate(const ViewSnapshot& snap, Real dt);
  /// Every open suction valve draws fluid and smoke in at its tip, for dt.
  void draw_in(const ViewSnapshot& snap, Real dt, bool fluid, bool smoke);

  std::vector<Vec3> gravity_;
  SmokeSettings smoke_settings_;
  FilmProperties film_properties_;
  std::uint64_t seed_;
  std::optional<double> time_;                 ///< the last frame's simulated time
  std::vector<std::unique_ptr<BloodFilm>> films_;  ///< per tissue, null: none
  std::vector<std::uint32_t> film_versions_;   ///< per tissue: the model version its film is on
  std::vector<Real> wound_fed_;                ///< per wound: its emitted volume fed so far
  std::vector<Real> vapour_seen_;              ///< per instrument: its vapour energy emitted so far
  std::unique_ptr<SmokeField> smoke_;
  DripLanding landing_;
  std::vector<BloodFilm*> film_pointers_;      ///< films_ as DripLanding takes them
  std::vector<std::span<const Vec3>> film_positions_;
  Real fed_ = 0, lost_ = 0, irrigated_ = 0;
  Real spilled_ = 0;                           ///< saline jetted at nothing within reach
  Real landed_ = 0, landed_blood_ = 0;         ///< of the films' drips, what landed on a film
  Real suctioned_ = 0, suctioned_blood_ = 0;
};

}  // namespace trocar
