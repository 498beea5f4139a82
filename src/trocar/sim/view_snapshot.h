#pragma once
/// What a renderer needs of one simulation step (docs/architecture.md "One step", its last stage):
/// deformed tissue positions, instrument poses, forces, contacts and timings. Built by the thread
/// that steps the simulation and read by the renderer on its own thread (through
/// core/triple_buffer.h), so the renderer never touches the Simulation. Vectors keep their
/// capacity: after the first capture of a scene, capture_view allocates only when more contacts
/// or tacks appear than ever before.
#include <cstdint>
#include <vector>

#include "trocar/core/obb.h"
#include "trocar/core/pose.h"
#include "trocar/core/types.h"
#include "trocar/sim/simulation.h"

namespace trocar {

/// One instrument as drawn.
struct InstrumentView {
  Pose pose;                    ///< world pose (m)
  Real jaw = 0;                 ///< closure 0..1
  Obb obb;                      ///< world OBB (m)
  Vec3 force = Vec3::Zero();    ///< force the device renders (N, on the instrument)
  Vec3 contact_centre = Vec3::Zero();  ///< mean of its contact points (m); pose origin when none
  std::uint32_t contacts = 0;   ///< instrument–tissue contacts this step
  Vec3 tip = Vec3::Zero();      ///< m: the working tip (the mesh's local origin)
  Vec3 forward = Vec3::UnitZ(); ///< unit: along the shaft, from the handle toward the tip
  /// Its suction-irrigator (InstrumentBody::suction) and its valves this step: the renderer draws
  /// fluid and smoke in at the tip and jets saline along `forward` (EffectsView).
  SuctionSpec suction_spec;
  bool suction = false;
  bool irrigation = false;
  bool energy = false;          ///< its electrode's pedal is down (Simulation::energy_on)
};

/// One instrument–tissue contact as drawn: the midpoint of the two triangles' intersection
/// segment and the tissue triangle's outward normal.
struct ContactView {
  Vec3 point = Vec3::Zero();    ///< m
  Vec3 normal = Vec3::Zero();   ///< unit, out of the tissue
  std::uint32_t instrument = 0; ///< instrument index
};

/// One holding attachment as drawn (a helical tack): where it enters and the surface's normal
/// there. The normal's sign is the tissue triangle's winding; the renderer turns the tack's head
/// towards the camera (the tacker fires from the cavity, where the scope is).
struct TackView {
  Vec3 point = Vec3::Zero();    ///< m, on the attachment's first surface (the prosthetic mesh)
  Vec3 normal = Vec3::Zero();   ///< unit normal of the second surface (the tissue it goes into)
};

/// One step as the renderer sees it.
struct ViewSnapshot {
  double time = 0;                               ///< simulated time (s)
  std::uint64_t step = 0;                        ///< steps done
  std::vector<std::vector<Vec3>> tissues;        ///< per tissue, its vertex positions (m)
  /// Per tissue: its model's version (TissueBody::model_version) and, copied when that changed,
  /// its triangles (a cut changes them: the renderer rebuilds the tissue's buffers).
  std::vector<std::uint32_t> tissue_versions;
  std::vector<std::vector<Triangle>> tissue_triangles;
  std::vector<std::vector<Vec3>> tissue_rest;    ///< per tissue, copied with its triangles: rest positions (m)
  /// Per tissue, 4 floats per vertex, empty while the tissue has none: what electrosurgery and
  /// bleeding did to its surface (docs/electrosurgery.md, "What is drawn"): coagulation 1 − e^(−Ω)
  /// and charring φ (the largest of its triangles'), the blood film (1 = 0.5 mm) and its stain.
  std::vector<std::vector<float>> tissue_effects;
  std::vector<VapourSource> vapour;              ///< per instrument: its electrode's smoke source
  /// Per tissue: whether it bleeds (a vessel); and every wound so far (Simulation::bleeding): the
  /// renderer runs the blood's flow over the surfaces from what each wound has bled.
  std::vector<std::uint8_t> tissue_bleeds;
  struct WoundView {
    std::uint32_t tissue = 0;   ///< world tissue index
    std::uint32_t vertex = 0;   ///< the bleeding point (a vertex of the tissue's current model)
    Real emitted = 0;           ///< m³ it has bled so far
    bool open = true;           ///< still bleeding (not sealed or clipped)
  };
  std::vector<WoundView> wounds;
  std::vector<InstrumentView> instruments;       ///< per instrument
  std::vector<ContactView> contacts;             ///< instrument–tissue contacts
  std::vector<TackView> tacks;                   ///< holding attachments (torn ones are not drawn)
  StageTimings timings;                          ///< µs per module, last step
  Real cell_size = 0;                            ///< OHC cell edge of the last detection (m; 0: none)
};

/// Copies what the renderer draws out of `sim` into `out` (reusing its storage).
void capture_view(const Simulation& sim, ViewSnapshot& out);

}  // namespace trocar
