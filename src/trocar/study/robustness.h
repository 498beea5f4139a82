#pragma once
/// The robustness suite (docs/robustness.md): every organ × material × instrument × motion ×
/// solver, the motions placed from each organ's own geometry, so that a target is checked on the
/// kind of case and not on one mesh or one preset.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/instruments.h"
#include "trocar/mesh/tri_mesh.h"
#include "trocar/response/settings.h"
#include "trocar/sim/simulation.h"
#include "trocar/sim/world.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/material.h"

namespace trocar {

/// One organ of the suite, in metres, centred on the origin.
struct SuiteOrgan {
  std::string name;    ///< e.g. "liver_sofa_smooth" or "lobe-2k-s1"
  std::string source;  ///< "shared", "generated" or the folder it came from
  TriMesh mesh;        ///< closed, outward, metres, centred (box centre at the origin)
  std::string preset;  ///< material preset (tissue/material.h)
};

/// The motions of the suite (placed by suite_world() from organ_target()).
enum class SuiteMotion : std::uint8_t {
  kPress,      ///< probe down onto the highest point to the press depth at 20 mm/s, held 0.3 s
  kSlide,      ///< the press, held 0.2 s, then 20 mm sideways at 40 mm/s while pressed, held 0.1 s
  kPokeSlow,   ///< from 5 mm above to the press depth at 0.2 m/s, held 0.2 s
  kPoke,       ///< the same at 1 m/s
  kPokeFast,   ///< the same at 2 m/s (reported; the targets stop at 1 m/s)
  kGraspLift,  ///< grasper down 2 mm into the top at 20 mm/s, jaws closed in 0.1 s, lifted 10 mm
  kDeepPress,  ///< from 5 mm above to the deep press depth at 20 mm/s, held 0.3 s
  kRest,       ///< the stability check: the instrument held 30 mm above the top for 0.5 s, no contact
};

/// "press", "slide", "poke-0.2", "poke-1", "poke-2", "grasp-lift", "deep-press", "rest".
const char* suite_motion_name(SuiteMotion motion);
/// The motion named `name`, or nothing.
std::optional<SuiteMotion> parse_suite_motion(std::string_view name);
/// Every motion: press, slide, poke-0.2, poke-1, poke-2, deep-press, grasp-lift, rest.
std::vector<SuiteMotion> all_suite_motions();
/// The instrument's top speed in the motion (m/s; 0 for rest).
Real suite_motion_speed(SuiteMotion motion);

/// Where an organ is touched: its highest vertex and the thickness below it.
struct OrganTarget {
  Vec3 top = Vec3::Zero();     ///< the highest vertex (max z), world (m)
  Real thickness = 0;          ///< along −z from top to where that vertical line leaves the organ (m)
  Real press_depth = 0;        ///< min(8 mm, 20 % of thickness) (m)
  Real deep_press_depth = 0;   ///< min(15 mm, 45 % of thickness) (m)
  Vec3 slide_direction = Vec3::UnitX();  ///< horizontal unit vector toward the organ's centre
};
/// The target of `mesh` (closed, metres). The vertical line is cast through the top vertex's
/// (x, y) shifted by 1 µm (so it does not run along the vertex's own edges).
OrganTarget organ_target(const TriMesh& mesh);

/// The generated family (mesh/organ_shapes.h) as suite organs, preset "liver".
std::vector<SuiteOrgan> generated_organs(std::uint64_t seed = 1);
/// The organ meshes of `dir` (OBJ, STL, PLY, VRML, VTK; instrument meshes — names with probe,
/// grasper, jaw, laparoscope, trocar — are left out), repaired, scaled to metres (the unit of
/// m, cm, mm that makes the longest extent nearest 15 cm on a log scale), centred; the preset from the name (liver, gallbladder, stomach,
/// abdominal_wall, else liver). A missing folder gives none; an unreadable mesh throws with its
/// file name.
std::vector<SuiteOrgan> organs_in(const std::filesystem::path& dir, const std::string& source);

/// A material family of the suite: a name and the mass-spring material it stands for.
struct SuiteMaterial {
  std::string name;              ///< "light-soft", "medium", "heavy-stiff", "light-stiff", "preset"
  MassSpringMaterial material;   ///< the families: mass > 0 (overrides the density), area and volume on
};
/// The material families, for every organ (masses 50 g–2 kg, k_structural 10–5000 N/m; damping
/// 0.5 1/s and spring damping 0.05 N·s/m, MassSpringMaterial's defaults; home springs 15 N/m per
/// kg of mass, the presets' ratio, so the organ holds its shape under gravity: without them
/// the hollow surface cannot carry its weight and the lobes fall onto their fixed base):
///  - "light-soft":  0.05 kg, k_structural 10,   k_bending 1,   k_area 10, k_volume 100, k_home 0.75;
///  - "medium":      0.3 kg,  k_structural 100,  k_bending 10,  k_area 10, k_volume 100, k_home 4.5;
///  - "heavy-stiff": 2 kg,    k_structural 500,  k_bending 50,  k_area 10, k_volume 300, k_home 30;
///  - "light-stiff": 0.05 kg, k_structural 5000, k_bending 500, k_area 10, k_volume 100, k_home 0.75
///    (the rest check's: the stiffest spring on the lightest vertices);
///  - "preset": the organ's own preset (SuiteOrgan::preset, tissue/material.h).
/// Throws trocar::Error for an unknown name.
SuiteMaterial suite_material(const std::string& name, const SuiteOrgan& organ);
/// The names suite_material() knows, in the order above.
std::vector<std::string> suite_material_names();
/// The default contact materials: light-soft, medium, heavy-stiff.
std::vector<std::string> suite_contact_material_names();
/// The material of the rest check: "light-stiff".
inline constexpr const char* kSuiteRestMaterial = "light-stiff";

/// An instrument family of the suite, in its local frame like make_hook_probe(): metres, tip at
/// the origin, shaft along +z.
struct SuiteInstrument {
  std::string name;     ///< "hook", "hook-mesh", "grasper", "probe10"
  InstrumentMesh mesh;  ///< jaw triangles for the grasper only
  bool grasper() const { return !mesh.jaw_triangles.empty(); }
};
/// "hook", "hook-mesh", "grasper", "probe10".
std::vector<std::string> suite_instrument_names();
/// The shared hook electrode's file name (in ../shared/data/meshes).
inline constexpr const char* kSuiteHookMeshFile = "probe_hook_electrode_lapgym.stl";
/// The instrument named `name`:
///  - "hook": make_hook_probe() (Ø4.5 mm shaft, 1.2 mm wire);
///  - "hook-mesh": the shared hook electrode, kSuiteHookMeshFile from the first of `mesh_dirs`
///    that holds it, mm → m, turned 180° about x (its hook points along +z in the file) and
///    moved so its lowest point is at z = 0 on the shaft's axis; nothing when no folder holds it;
///  - "grasper": make_grasper() (5 mm);
///  - "probe10": a blunt Ø10 mm probe, make_capsule(5 mm radius, 30 cm, 16 segments, 4 rings)
///    moved up by its radius so the rounded tip is at the origin.
/// Throws trocar::Error for an unknown name or an unreadable hook mesh.
std::optional<SuiteInstrument> suite_instrument(const std::string& name,
                                                const std::vector<std::filesystem::path>& mesh_dirs = {});

/// A solver of the suite: the tissue's integrator and, for the implicit one, the response method.
struct SuiteSolver {
  std::string name;  ///< "xpbd", or a response method's name ("sdf", "project", "obb", ...)
  IntegratorKind integrator = IntegratorKind::kImplicitEuler;
  /// The response method of the implicit solvers. xpbd: its contact is inside the solver and no
  /// method applies; the settings' method is kept at sdf (whose contact margin, friction and
  /// grasp closure the solver's contact reads).
  ResponseMethod method = ResponseMethod::kSdf;
};
/// "xpbd" (IntegratorKind::kXpbd) or a response method on implicit Euler; nothing for another name.
std::optional<SuiteSolver> parse_suite_solver(std::string_view name);
/// The names parse_suite_solver() knows: xpbd, sdf, project, obb, primitive, normal.
std::vector<std::string> suite_solver_names();

/// A world for one case: the organ (renumbered for locality, bottom 20 % of its height fixed,
/// gravity −z, `material`, `integrator`) and `instrument` moving as `motion` prescribes (rest:
/// held 30 mm above the top). Pass the grasper for grasp-lift (its jaws close on the tissue).
World suite_world(const SuiteOrgan& organ, SuiteMotion motion, const MassSpringMaterial& material,
                  const SuiteInstrument& instrument, IntegratorKind integrator, Real& duration);
/// The same with the organ's preset, implicit Euler, the hook (make_hook_probe) for the probe
/// motions and the grasper for grasp-lift.
World suite_world(const SuiteOrgan& organ, SuiteMotion motion, Real& duration);

/// The suite's simulation settings for `method`: detection every 1 ms, stiffness 2000 N/m,
/// damping 5 N·s/m, max_force 10 N (the shipped scenes' response); metrics on.
SimulationSettings suite_settings(ResponseMethod method);

/// The figures of one run.
struct SuiteRun {
  std::string organ, source, motion;
  std::string solver;       ///< "xpbd", "sdf", "project", ...
  std::string integrator;   ///< "xpbd" or "implicit-euler"
  std::string method;       ///< the response method applied ("sdf", ...; "in-solver" for xpbd)
  std::string material;     ///< suite material name
  std::string instrument;   ///< suite instrument name
  std::size_t vertices = 0, triangles = 0;
  std::size_t steps = 0;    ///< steps simulated (an unstable run stops at its first unstable step)
  double step_median_us = 0, step_p99_us = 0;  ///< the step without the metrics stage
  double deform_median_us = 0, deform_p99_us = 0;  ///< the whole deformation stage
  double projection_median_us = 0;  ///< of it, the sdf projection (steps with contact)
  /// Deformation without the sdf projection (the integrator) per vertex over the steps with
  /// contact (ns; median), 0 without contact (see contact_steps).
  double deform_ns_per_vertex_contact = 0;
  double cg_mean = 0;          ///< CG iterations per step, mean
  double cg_mean_contact = 0;  ///< the same over the steps with contact (contact_steps)
  std::uint32_t cg_max = 0;
  std::uint32_t substeps_max = 0;  ///< StepMetrics::substeps, max (xpbd; 0 otherwise)
  Real constraint_error_max = 0;     ///< StepMetrics::constraint_error over the steps: max
  Real constraint_error_median = 0;  ///< and median
  std::size_t contact_steps = 0;  ///< steps with a detected contact or a force on the instrument
  Real penetration_p99 = 0;  ///< m, over steps with a vertex inside (0 if none)
  Real penetration_max = 0;  ///< m
  std::uint64_t tunneling = 0;
  Real force_max = 0;        ///< |instrument force| max (N, clamped as the device sees it)
  Real raw_force_max = 0;    ///< unclamped (N)
  bool stable = true;       ///< every step stable (core/stability.h)
  /// The rest check (motion rest only): total energy E = kinetic + elastic (StepMetrics), mean
  /// over the first 0.1 s and over the last 0.1 s of the run (J); drift = (last − first)/first
  /// (0 when first is 0); energy_grew = drift > kSuiteEnergyGrowth.
  bool rest = false;
  double energy_first = 0, energy_last = 0;
  double energy_drift = 0;
  bool energy_grew = false;
};
/// The rest check flags a growth of the total energy above this share (+1 %).
inline constexpr double kSuiteEnergyGrowth = 0.01;

/// Runs one case: suite_world() with the material, instrument and the solver's integrator, and
/// suite_settings(solver.method), dt = 1 ms.
SuiteRun run_suite_case(const SuiteOrgan& organ, SuiteMotion motion, const SuiteMaterial& material,
                        const SuiteInstrument& instrument, const SuiteSolver& solver);
/// Runs one case of the preset world (suite_world(organ, motion, duration)) with `method` on
/// implicit Euler and suite_settings(method), dt = 1 ms.
SuiteRun run_suite_case(const SuiteOrgan& organ, SuiteMotion motion, ResponseMethod method);

}  // namespace trocar
