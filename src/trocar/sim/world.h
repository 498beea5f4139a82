#pragma once
/// What a simulation simulates: tissues, instruments and rigid obstacles, each with a name.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/instrument/instrument.h"
#include "trocar/mesh/tri_mesh.h"
#include "trocar/core/motion.h"
#include "trocar/electrosurgery/bleeding.h"
#include "trocar/electrosurgery/electrode.h"
#include "trocar/electrosurgery/suction.h"
#include "trocar/electrosurgery/thermal.h"
#include "trocar/tissue/energy.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/material.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {

/// A deforming organ (role kTissue). Not movable: the integrator refers to the settings, so
/// the World keeps each tissue behind a unique_ptr.
struct TissueBody {
  std::string name;                  ///< scene name
  MassSpringSettings settings;       ///< immutable model (metres, kg)
  MassSpringState state;             ///< positions (m) and velocities (m/s)
  MassSpringIntegrator integrator;   ///< steps `state`
  ElasticEnergyMeter energy;         ///< the per-step elastic energy metric
  TissueLoads loads;                 ///< external forces of the current step (N)
  /// The mesh's (u, v) per triangle corner (3 per settings.triangles entry, same order), for a
  /// renderer's texture; empty when the mesh has none.
  std::vector<Vec2> texcoords;
  /// Jaws may hold its vertices (scene "graspable"). The groin's abdominal wall is not: a grasper
  /// takes the mesh or peritoneum lying on it, never a bite of the wall beneath.
  bool graspable = true;
  /// Simulated time (s) at which it enters the body (scene "enters_at"): until then it waits
  /// outside, far from everything and not stepped; then it is placed at its rest shape, at rest
  /// (the prosthetic mesh, brought in through a port after the sac is reduced). 0: from the start.
  Real enters_at = 0;
  /// How it heats and burns under an electrode (scene key "thermal"; docs/electrosurgery.md).
  ThermalProperties thermal;
  /// Coagulated tissue is stiffer: a coagulated triangle's edge springs take this factor on their
  /// stiffness and keep the length they had then as their rest length (scene key
  /// "coagulation_stiffening"; 1: unchanged). Elastography of thermal lesions finds them several
  /// times stiffer than the tissue around them (Wu et al., Magn Reson Med 45:80, 2001).
  Real coagulation_stiffening = 3;
  /// A vessel that bleeds when cut, torn or burnt through without sealing (scene key "bleeds";
  /// docs/electrosurgery.md, "Bleeding"). Empty: it does not bleed.
  std::optional<VesselSpec> bleeds;
  /// N: a grasper pulling it harder than this tears it (a bleeding tissue only; 0: never). The
  /// largest acceptable tractive forces on porcine tissues run 1.25–11.43 N (Rodrigues et al.,
  /// Surg Endosc 2012; docs/assessment.md), a vessel's wall among the weakest.
  Real tear_force = 0;
  /// Counts the changes of the model during a simulation (a cut, coagulation): whatever keeps
  /// something per vertex or triangle of this tissue (a renderer's buffers) rebuilds it when
  /// this moved.
  std::uint32_t model_version = 0;

  /// Builds the model from a mesh already placed in the world (metres).
  TissueBody(std::string body_name, const TriMesh& world_mesh, const MassSpringMaterial& material,
             const FixedSelection& fixed, const Vec3& gravity, IntegratorKind kind);
  /// Takes a model already made (the tissue after a cut, Simulation's remodelling), at rest; the
  /// integrator gets these options.
  TissueBody(std::string body_name, MassSpringSettings model, IntegratorKind kind, ImplicitOptions implicit,
             XpbdOptions xpbd);
  TissueBody(const TissueBody&) = delete;
  TissueBody& operator=(const TissueBody&) = delete;
};

/// A rigid instrument (role kInstrument) moved by keyframes.
struct InstrumentBody {
  std::string name;          ///< scene name
  Instrument instrument;     ///< mesh in its local frame (m), pose, OBB, top vertex, jaws
  KeyframeMotion motion;     ///< scripted pose and jaw over time
  /// Thickness used by the tunneling metric (m): twice the smallest half-extent of the OBB.
  Real thickness = 0;
  /// The trocar port it enters through (scene "port"). Instruments naming the same port take
  /// turns: one is in the body, the others wait outside until an exchange (Simulation::exchange).
  /// Empty: a port of its own.
  std::string port;
  /// What it is: the scene generator's name ("grasper", "tacker", "hook-probe", ...) or "custom"
  /// for a mesh from a file. The procedure fires only a "tacker".
  std::string tool = "custom";
  /// Its electrode (scene key "electrode"; power 0: none): with the pedal down
  /// (Simulation::set_energy) it heats the tissue it touches.
  ElectrodeSpec electrode;
  /// Its suction and irrigation (scene key "suction"; flows 0: none): while a valve is open
  /// (Simulation::set_suction, set_irrigation) it draws fluid and smoke in at the tip, or jets
  /// saline out of it (drawn and flowed by the renderer: docs/electrosurgery.md).
  SuctionSpec suction = SuctionSpec::none();
};

/// Static geometry (role kRigid): bones, a table, ports. Only detected, never moved.
struct RigidBody {
  std::string name;   ///< scene name
  TriMesh mesh;       ///< world positions (m)
};

/// Everything in one scene. Tissues are heap-held so that their addresses stay fixed.
struct World {
  std::vector<std::unique_ptr<TissueBody>> tissues;  ///< organs
  std::vector<InstrumentBody> instruments;           ///< tools
  std::vector<RigidBody> rigids;                      ///< static obstacles

  /// Adds a tissue and returns it. The mesh is used in its own vertex order; the scene loader
  /// renumbers a tissue for memory locality first (mesh/renumber.h, 3–5 % faster steps), which a
  /// program building its World directly can do too.
  TissueBody& add_tissue(std::string name, const TriMesh& world_mesh, const MassSpringMaterial& material,
                         const FixedSelection& fixed, const Vec3& gravity, IntegratorKind kind);
  /// Adds an instrument (mesh in its local frame, metres); the thickness comes from its OBB.
  InstrumentBody& add_instrument(std::string name, Instrument instrument, KeyframeMotion motion);
  /// Adds a rigid obstacle (mesh in world, metres).
  RigidBody& add_rigid(std::string name, TriMesh world_mesh);
  /// The tissue called `name` (its index in `*index` when given), or null: the callers say what
  /// was missing, and where.
  const TissueBody* find_tissue(std::string_view name, std::size_t* index = nullptr) const;
};

}  // namespace trocar
