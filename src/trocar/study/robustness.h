#pragma once
/// The robustness suite (docs/robustness.md): every organ × every motion × every response
/// method, the motions placed from each organ's own geometry, so that a target is checked on
/// the kind of case and not on one mesh.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"
#include "trocar/response/settings.h"
#include "trocar/sim/simulation.h"
#include "trocar/sim/world.h"

namespace trocar {

/// One organ of the suite, in metres, centred on the origin.
struct SuiteOrgan {
  std::string name;    ///< e.g. "liver_sofa_smooth" or "lobe-2k-s1"
  std::string source;  ///< "shared", "generated" or the folder it came from
  TriMesh mesh;        ///< closed, outward, metres, centred (box centre at the origin)
  std::string preset;  ///< material preset (tissue/material.h)
};

/// The motions of the suite (placed by place_motion()).
enum class SuiteMotion : std::uint8_t {
  kPress,      ///< probe down onto the highest point to the press depth at 20 mm/s, held 0.3 s
  kSlide,      ///< the press, held 0.2 s, then 20 mm sideways at 40 mm/s while pressed, held 0.1 s
  kPokeSlow,   ///< from 5 mm above to the press depth at 0.2 m/s, held 0.2 s
  kPoke,       ///< the same at 1 m/s
  kPokeFast,   ///< the same at 2 m/s (reported; the targets stop at 1 m/s)
  kGraspLift,  ///< grasper down 2 mm into the top at 20 mm/s, jaws closed in 0.1 s, lifted 10 mm
};

/// "press", "slide", "poke-0.2", "poke-1", "poke-2", "grasp-lift".
const char* suite_motion_name(SuiteMotion motion);
/// Every motion, in the order above.
std::vector<SuiteMotion> all_suite_motions();
/// The instrument's top speed in the motion (m/s).
Real suite_motion_speed(SuiteMotion motion);

/// Where an organ is touched: its highest vertex and the thickness below it.
struct OrganTarget {
  Vec3 top = Vec3::Zero();     ///< the highest vertex (max z), world (m)
  Real thickness = 0;          ///< along −z from top to where that vertical line leaves the organ (m)
  Real press_depth = 0;        ///< min(8 mm, 20 % of thickness) (m)
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

/// A world for one case: the organ (renumbered for locality, bottom 20 % of its height fixed,
/// gravity −z, its preset, implicit Euler) and the instrument moving as `motion` prescribes.
World suite_world(const SuiteOrgan& organ, SuiteMotion motion, Real& duration);

/// The suite's simulation settings for `method`: detection every 1 ms, stiffness 2000 N/m,
/// damping 5 N·s/m, max_force 10 N (the shipped scenes' response); metrics on.
SimulationSettings suite_settings(ResponseMethod method);

/// The figures of one run.
struct SuiteRun {
  std::string organ, source, motion, method;
  std::size_t vertices = 0, triangles = 0;
  std::size_t steps = 0;
  double step_median_us = 0, step_p99_us = 0;  ///< the step without the metrics stage
  double deform_median_us = 0, deform_p99_us = 0;  ///< the whole deformation stage
  double projection_median_us = 0;  ///< of it, the sdf projection (steps with contact)
  /// Deformation without the sdf projection (the integrator) per vertex over the steps with
  /// contact (ns; median), 0 without contact (see contact_steps).
  double deform_ns_per_vertex_contact = 0;
  double cg_mean = 0;          ///< CG iterations per step, mean
  double cg_mean_contact = 0;  ///< the same over the steps with contact (contact_steps)
  std::uint32_t cg_max = 0;
  std::size_t contact_steps = 0;  ///< steps with a detected contact or a force on the instrument
  Real penetration_p99 = 0;  ///< m, over steps with a vertex inside (0 if none)
  Real penetration_max = 0;  ///< m
  std::uint64_t tunneling = 0;
  Real force_max = 0;        ///< |instrument force| max (N, clamped as the device sees it)
  Real raw_force_max = 0;    ///< unclamped (N)
  bool stable = true;
};

/// Runs one case with `method` and suite_settings(method), dt = 1 ms.
SuiteRun run_suite_case(const SuiteOrgan& organ, SuiteMotion motion, ResponseMethod method);

}  // namespace trocar
