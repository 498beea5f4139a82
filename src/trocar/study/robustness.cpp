#include "trocar/study/robustness.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "trocar/core/error.h"
#include "trocar/core/statistics.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/organ_shapes.h"
#include "trocar/mesh/renumber.h"
#include "trocar/mesh/repair.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"
#include "trocar/tissue/material.h"

namespace trocar {
namespace {

constexpr Real kPressSpeed = 0.02;     ///< m/s, the press and the grasp's approach
constexpr Real kSlideSpeed = 0.04;     ///< m/s (40 mm/s, docs/robustness.md)
constexpr Real kSlideLength = 0.02;    ///< m
constexpr Real kApproach = 0.005;      ///< m above the top where every motion starts
constexpr Real kMaxPress = 0.008;      ///< m
constexpr Real kPressFraction = 0.2;   ///< of the local thickness
constexpr Real kDeepPress = 0.015;     ///< m, the deep press
constexpr Real kDeepFraction = 0.45;   ///< of the local thickness (deep press)
constexpr Real kFixedFraction = 0.2;   ///< bottom share of the organ's height held fixed
constexpr Real kRestHeight = 0.03;     ///< m above the top where the rest check holds the instrument
constexpr Real kRestDuration = 0.5;    ///< s, the rest check
constexpr Real kEnergyWindow = 0.1;    ///< s, the rest check's first and last windows
constexpr Real kProbe10Radius = 0.005; ///< m, the blunt Ø10 mm probe
constexpr Real kProbe10Length = 0.30;  ///< m, its shaft (as the hook's and the grasper's)

/// Appends a keyframe `length / speed` after the last one (or `hold` seconds when speed is 0).
void go(std::vector<Keyframe>& keys, const Vec3& to, Real speed, Real jaw = -1) {
  Keyframe k = keys.back();
  const Real length = (to - k.position).norm();
  k.t += speed > 0 ? std::max(length / speed, Real{1e-3}) : 0;
  k.position = to;
  if (jaw >= 0) k.jaw = jaw;
  keys.push_back(k);
}
void hold(std::vector<Keyframe>& keys, Real seconds, Real jaw = -1) {
  Keyframe k = keys.back();
  k.t += seconds;
  if (jaw >= 0) k.jaw = jaw;
  keys.push_back(k);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Centres the mesh's box on the origin.
void centre(TriMesh& mesh) {
  const Vec3 c = Aabb::of_points(mesh.positions).center();
  for (Vec3& p : mesh.positions) p -= c;
}

}  // namespace

const char* suite_motion_name(SuiteMotion motion) {
  switch (motion) {
    case SuiteMotion::kPress: return "press";
    case SuiteMotion::kSlide: return "slide";
    case SuiteMotion::kPokeSlow: return "poke-0.2";
    case SuiteMotion::kPoke: return "poke-1";
    case SuiteMotion::kPokeFast: return "poke-2";
    case SuiteMotion::kGraspLift: return "grasp-lift";
    case SuiteMotion::kDeepPress: return "deep-press";
    case SuiteMotion::kRest: return "rest";
  }
  return "press";
}

std::optional<SuiteMotion> parse_suite_motion(std::string_view name) {
  for (const SuiteMotion m : all_suite_motions())
    if (name == suite_motion_name(m)) return m;
  return std::nullopt;
}

std::vector<SuiteMotion> all_suite_motions() {
  return {SuiteMotion::kPress,    SuiteMotion::kSlide,     SuiteMotion::kPokeSlow,  SuiteMotion::kPoke,
          SuiteMotion::kPokeFast, SuiteMotion::kDeepPress, SuiteMotion::kGraspLift, SuiteMotion::kRest};
}

Real suite_motion_speed(SuiteMotion motion) {
  switch (motion) {
    case SuiteMotion::kSlide: return kSlideSpeed;
    case SuiteMotion::kPokeSlow: return 0.2;
    case SuiteMotion::kPoke: return 1.0;
    case SuiteMotion::kPokeFast: return 2.0;
    case SuiteMotion::kRest: return 0;
    case SuiteMotion::kPress:
    case SuiteMotion::kDeepPress:
    case SuiteMotion::kGraspLift: return kPressSpeed;
  }
  return kPressSpeed;
}

OrganTarget organ_target(const TriMesh& mesh) {
  OrganTarget target;
  if (mesh.positions.empty()) return target;
  const auto top = std::max_element(mesh.positions.begin(), mesh.positions.end(),
                                    [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });
  target.top = *top;
  // The vertical line through (x, y), nudged off the vertex: its crossings with the triangles'
  // xy projections (2-D barycentric coordinates), the highest below the top is where it leaves.
  const Real x = top->x() + 1e-6, y = top->y() + 1e-6;
  Real exit = -std::numeric_limits<Real>::infinity();
  Real lowest = std::numeric_limits<Real>::infinity();
  for (const Triangle& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3& b = mesh.positions[t[1]];
    const Vec3& c = mesh.positions[t[2]];
    const Real det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(det) < 1e-30) continue;
    const Real u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
    const Real v = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
    if (u < 0 || v < 0 || u + v > 1) continue;
    const Real z = a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z());
    lowest = std::min(lowest, z);
    if (z < top->z() - 1e-5) exit = std::max(exit, z);
  }
  if (!std::isfinite(exit)) exit = std::isfinite(lowest) ? lowest : Aabb::of_points(mesh.positions).min.z();
  target.thickness = std::max(top->z() - exit, Real{0});
  target.press_depth = std::min(kMaxPress, kPressFraction * target.thickness);
  target.deep_press_depth = std::min(kDeepPress, kDeepFraction * target.thickness);
  const Vec3 centre_point = Aabb::of_points(mesh.positions).center();
  Vec3 toward(centre_point.x() - top->x(), centre_point.y() - top->y(), 0);
  if (toward.norm() < 1e-3) {
    // At the centre already: along the organ's longer horizontal extent.
    const Vec3 size = Aabb::of_points(mesh.positions).size();
    toward = size.x() >= size.y() ? Vec3::UnitX() : Vec3::UnitY();
  }
  target.slide_direction = toward.normalized();
  return target;
}

std::vector<SuiteOrgan> generated_organs(std::uint64_t seed) {
  std::vector<SuiteOrgan> out;
  for (const OrganShapeSpec& spec : organ_family(seed)) {
    SuiteOrgan organ{spec.name, "generated", make_organ_shape(spec), "liver"};
    centre(organ.mesh);
    out.push_back(std::move(organ));
  }
  return out;
}

std::vector<SuiteOrgan> organs_in(const std::filesystem::path& dir, const std::string& source) {
  std::vector<SuiteOrgan> out;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return out;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file()) continue;
    const std::string ext = lower(entry.path().extension().string());
    if (ext != ".obj" && ext != ".stl" && ext != ".ply" && ext != ".wrl" && ext != ".vtk") continue;
    const std::string stem = lower(entry.path().stem().string());
    bool tool = false;
    for (const char* word : {"probe", "grasper", "jaw", "laparoscope", "trocar", "scissor", "needle"})
      tool = tool || stem.find(word) != std::string::npos;
    if (!tool) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  // One organ per stem: the same mesh in two formats (liver .obj and .wrl) runs once.
  std::vector<std::string> stems;
  for (const std::filesystem::path& file : files) {
    const std::string stem = file.stem().string();
    if (std::find(stems.begin(), stems.end(), stem) != stems.end()) continue;
    stems.push_back(stem);
    TriMesh mesh = load_mesh(file);
    repair(mesh);
    if (mesh.triangles.empty()) throw Error(file.string() + ": no triangles after repair");
    // File units from the box: of metres, centimetres and millimetres, the one that makes the
    // longest extent nearest 15 cm on a log scale (organs are 3–50 cm long).
    const Real extent = Aabb::of_points(mesh.positions).size().maxCoeff();
    Real scale = 1;
    for (const Real s : {Real{1e-2}, Real{1e-3}})
      if (std::abs(std::log(extent * s / 0.15)) < std::abs(std::log(extent * scale / 0.15))) scale = s;
    for (Vec3& p : mesh.positions) p *= scale;
    centre(mesh);
    const std::string name = lower(stem);
    std::string preset = "liver";
    for (const char* p : {"gallbladder", "stomach", "abdominal_wall", "duodenum"})
      if (name.find(p) != std::string::npos) preset = std::string(p) == "duodenum" ? "stomach" : p;
    out.push_back({stem, source, std::move(mesh), preset});
  }
  return out;
}

std::vector<std::string> suite_material_names() {
  return {"light-soft", "medium", "heavy-stiff", "light-stiff", "preset"};
}

std::vector<std::string> suite_contact_material_names() { return {"light-soft", "medium", "heavy-stiff"}; }

SuiteMaterial suite_material(const std::string& name, const SuiteOrgan& organ) {
  if (name == "preset") return {name, material_preset(organ.preset)};
  // Density and sheet thickness unused (the mass overrides them); damping 0.5 1/s and spring
  // damping 0.05 N·s/m (MassSpringMaterial's defaults). Home springs k_home = 15 N/m per kg of
  // mass (the presets' ratio: liver 30 for 1.5 kg, gallbladder 1 for 70 g): the organ's support
  // by its neighbours. Without them a hollow surface with these volume terms cannot carry its
  // weight: the generated lobe's top drops 24 mm onto the fixed base for every family but
  // light-stiff, and no motion reaches it.
  MassSpringMaterial m;
  if (name == "light-soft") {
    m = {.mass = 0.05, .density = 1060, .sheet_thickness = 0.002, .k_structural = 10, .k_bending = 1,
         .damping = 0.5, .spring_damping = 0.05, .k_area = 10, .k_volume = 100, .k_home = 0.75};
  } else if (name == "medium") {
    m = {.mass = 0.3, .density = 1060, .sheet_thickness = 0.002, .k_structural = 100, .k_bending = 10,
         .damping = 0.5, .spring_damping = 0.05, .k_area = 10, .k_volume = 100, .k_home = 4.5};
  } else if (name == "heavy-stiff") {
    m = {.mass = 2.0, .density = 1060, .sheet_thickness = 0.002, .k_structural = 500, .k_bending = 50,
         .damping = 0.5, .spring_damping = 0.05, .k_area = 10, .k_volume = 300, .k_home = 30};
  } else if (name == "light-stiff") {
    m = {.mass = 0.05, .density = 1060, .sheet_thickness = 0.002, .k_structural = 5000, .k_bending = 500,
         .damping = 0.5, .spring_damping = 0.05, .k_area = 10, .k_volume = 100, .k_home = 0.75};
  } else {
    std::string known;
    for (const std::string& n : suite_material_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown suite material \"" + name + "\" (known: " + known + ")");
  }
  return {name, m};
}

std::vector<std::string> suite_instrument_names() { return {"hook", "hook-mesh", "grasper", "probe10"}; }

std::optional<SuiteInstrument> suite_instrument(const std::string& name,
                                                const std::vector<std::filesystem::path>& mesh_dirs) {
  if (name == "hook") return SuiteInstrument{name, make_hook_probe()};
  if (name == "grasper") return SuiteInstrument{name, make_grasper()};
  if (name == "probe10") {
    InstrumentMesh probe{make_capsule(kProbe10Radius, kProbe10Length, 16, 4), {}};
    for (Vec3& p : probe.mesh.positions) p.z() += kProbe10Radius;  // the rounded tip's end at the origin
    return SuiteInstrument{name, std::move(probe)};
  }
  if (name == "hook-mesh") {
    for (const std::filesystem::path& dir : mesh_dirs) {
      const std::filesystem::path file = dir / kSuiteHookMeshFile;
      std::error_code ec;
      if (!std::filesystem::is_regular_file(file, ec)) continue;
      InstrumentMesh hook{load_mesh(file), {}};
      if (hook.mesh.triangles.empty()) throw Error(file.string() + ": no triangles");
      // Millimetres; the hook along +z of the file and the shaft along −z: turned 180° about x
      // (y → −y, z → −z, orientation kept), then the lowest point up to z = 0.
      Real lowest = std::numeric_limits<Real>::infinity();
      for (Vec3& p : hook.mesh.positions) {
        p = Vec3(p.x(), -p.y(), -p.z()) * Real{1e-3};
        lowest = std::min(lowest, p.z());
      }
      for (Vec3& p : hook.mesh.positions) p.z() -= lowest;
      hook.mesh.normals.clear();
      return SuiteInstrument{name, std::move(hook)};
    }
    return std::nullopt;
  }
  std::string known;
  for (const std::string& n : suite_instrument_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown suite instrument \"" + name + "\" (known: " + known + ")");
}

std::vector<std::string> suite_solver_names() { return {"xpbd", "sdf", "project", "obb", "primitive", "normal"}; }

std::optional<SuiteSolver> parse_suite_solver(std::string_view name) {
  if (name == "xpbd") return SuiteSolver{"xpbd", IntegratorKind::kXpbd, ResponseMethod::kSdf};
  const std::optional<ResponseMethod> method = parse_response_method(name);
  if (!method) return std::nullopt;
  return SuiteSolver{std::string(name), IntegratorKind::kImplicitEuler, *method};
}

World suite_world(const SuiteOrgan& organ, SuiteMotion motion, const MassSpringMaterial& material,
                  const SuiteInstrument& tool, IntegratorKind integrator, Real& duration) {
  World world;
  const Aabb box = Aabb::of_points(organ.mesh.positions);
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, box.min.z() + kFixedFraction * box.size().z()), Vec3::UnitZ()};
  const std::vector<std::uint32_t> order = locality_vertex_order(organ.mesh);
  world.add_tissue(organ.name, renumber_vertices(organ.mesh, order), material, fixed, Vec3(0, 0, -9.81), integrator);

  const OrganTarget target = organ_target(organ.mesh);
  const Vec3 above = target.top + Vec3(0, 0, kApproach);
  const Vec3 pressed = target.top - Vec3(0, 0, target.press_depth);
  std::vector<Keyframe> keys(1);
  keys[0].position = above;
  Instrument instrument(tool.mesh.mesh);
  if (tool.grasper()) instrument.set_jaw_triangles(tool.mesh.jaw_triangles);
  switch (motion) {
    case SuiteMotion::kRest:
      keys[0].position = target.top + Vec3(0, 0, kRestHeight);
      hold(keys, kRestDuration);
      break;
    case SuiteMotion::kGraspLift: {
      hold(keys, 0.05);
      const Vec3 bite = target.top - Vec3(0, 0, std::min(Real{0.002}, target.press_depth));
      go(keys, bite, kPressSpeed);
      hold(keys, 0.1, 1.0);
      go(keys, bite + Vec3(0, 0, 0.01), kPressSpeed);
      hold(keys, 0.1);
      break;
    }
    case SuiteMotion::kPress:
      hold(keys, 0.05);
      go(keys, pressed, kPressSpeed);
      hold(keys, 0.3);
      break;
    case SuiteMotion::kDeepPress:
      hold(keys, 0.05);
      go(keys, target.top - Vec3(0, 0, target.deep_press_depth), kPressSpeed);
      hold(keys, 0.3);
      break;
    case SuiteMotion::kSlide:
      hold(keys, 0.05);
      go(keys, pressed, kPressSpeed);
      hold(keys, 0.2);
      go(keys, pressed + kSlideLength * target.slide_direction, kSlideSpeed);
      hold(keys, 0.1);
      break;
    case SuiteMotion::kPokeSlow:
    case SuiteMotion::kPoke:
    case SuiteMotion::kPokeFast:
      hold(keys, 0.05);
      go(keys, pressed, suite_motion_speed(motion));
      hold(keys, 0.2);
      break;
  }
  duration = keys.back().t;
  world.add_instrument(tool.name, std::move(instrument), KeyframeMotion(std::move(keys)));
  return world;
}

World suite_world(const SuiteOrgan& organ, SuiteMotion motion, Real& duration) {
  const bool grasp = motion == SuiteMotion::kGraspLift;
  const SuiteInstrument tool{grasp ? "grasper" : "hook", grasp ? make_grasper() : make_hook_probe()};
  return suite_world(organ, motion, material_preset(organ.preset), tool, IntegratorKind::kImplicitEuler, duration);
}

SimulationSettings suite_settings(ResponseMethod method) {
  SimulationSettings settings;
  settings.collision_period = 0.001;
  settings.response.method = method;
  settings.response.stiffness = 2000;
  settings.response.damping = 5;
  settings.response.max_force = 10;
  return settings;
}

namespace {

/// Steps `world` for `duration` at 1 ms and fills the figures of `run` (names set by the caller).
void measure_run(World world, const SimulationSettings& settings, Real duration, SuiteRun& run) {
  Simulation sim(std::move(world), settings);
  constexpr Real dt = 0.001;
  const std::size_t steps = step_count(duration, dt);
  const std::size_t window = std::min(steps, static_cast<std::size_t>(std::lround(kEnergyWindow / dt)));
  std::vector<double> step_us, deform_us, deform_contact_ns, projection_us, depths, constraint_errors;
  step_us.reserve(steps);
  deform_us.reserve(steps);
  constraint_errors.reserve(steps);
  double cg_sum = 0, cg_contact_sum = 0, energy_first = 0, energy_last = 0;
  std::size_t first_count = 0, last_count = 0;
  const double per_vertex = 1e3 / static_cast<double>(std::max<std::size_t>(run.vertices, 1));
  std::size_t s = 0;  // the step's index
  const DriveResult result = drive(sim, dt, steps, [&](const StepMetrics& m) {
    step_us.push_back(m.timings.step - m.timings.metrics);
    deform_us.push_back(m.timings.deformation);
    cg_sum += m.cg_iterations;
    run.cg_max = std::max(run.cg_max, m.cg_iterations);
    run.substeps_max = std::max(run.substeps_max, m.substeps);
    constraint_errors.push_back(m.constraint_error);
    Real force = 0;
    for (const InstrumentMetrics& im : sim.instrument_metrics()) {
      force = std::max(force, im.raw_force.norm());
      run.force_max = std::max(run.force_max, im.force.norm());
    }
    run.raw_force_max = std::max(run.raw_force_max, force);
    if (m.contacts > 0 || force > 0) {  // sdf keeps the surfaces apart: its contact is the force
      ++run.contact_steps;
      cg_contact_sum += m.cg_iterations;
      deform_contact_ns.push_back((m.timings.deformation - m.timings.projection) * per_vertex);
      projection_us.push_back(m.timings.projection);
    }
    if (m.vertices_inside > 0) depths.push_back(m.penetration_max);
    run.penetration_max = std::max(run.penetration_max, m.penetration_max);
    run.tunneling += m.tunneling_events;
    const double energy = m.kinetic_energy + m.elastic_energy;
    if (s < window) {
      energy_first += energy;
      ++first_count;
    }
    if (s + window >= steps) {
      energy_last += energy;
      ++last_count;
    }
    ++s;
  });
  run.steps = result.steps;
  run.stable = result.stable;
  run.step_median_us = median(step_us);
  run.step_p99_us = quantile(step_us, 0.99);
  run.deform_median_us = median(deform_us);
  run.deform_p99_us = quantile(deform_us, 0.99);
  run.deform_ns_per_vertex_contact = median(deform_contact_ns);
  run.projection_median_us = median(projection_us);
  run.cg_mean = step_us.empty() ? 0 : cg_sum / static_cast<double>(step_us.size());
  run.cg_mean_contact = run.contact_steps == 0 ? 0 : cg_contact_sum / static_cast<double>(run.contact_steps);
  run.constraint_error_max = constraint_errors.empty() ? 0 : *std::max_element(constraint_errors.begin(), constraint_errors.end());
  run.constraint_error_median = median(constraint_errors);
  run.penetration_p99 = quantile(depths, 0.99);
  if (run.rest) {
    run.energy_first = first_count == 0 ? 0 : energy_first / static_cast<double>(first_count);
    // An unstable run stops early: its last window is what it reached (growth, or non-finite).
    run.energy_last = last_count == 0 ? std::numeric_limits<double>::infinity() : energy_last / static_cast<double>(last_count);
    if (!run.stable) run.energy_last = std::numeric_limits<double>::infinity();
    run.energy_drift = run.energy_first > 0 ? (run.energy_last - run.energy_first) / run.energy_first : 0;
    if (!std::isfinite(run.energy_drift)) run.energy_drift = std::numeric_limits<double>::infinity();
    run.energy_grew = !run.stable || run.energy_drift > kSuiteEnergyGrowth;
  }
}

}  // namespace

SuiteRun run_suite_case(const SuiteOrgan& organ, SuiteMotion motion, const SuiteMaterial& material,
                        const SuiteInstrument& instrument, const SuiteSolver& solver) {
  Real duration = 0;
  World world = suite_world(organ, motion, material.material, instrument, solver.integrator, duration);
  SuiteRun run;
  run.organ = organ.name;
  run.source = organ.source;
  run.motion = suite_motion_name(motion);
  run.solver = solver.name;
  run.integrator = integrator_name(solver.integrator);
  run.method = solver.integrator == IntegratorKind::kXpbd ? "in-solver" : response_method_name(solver.method);
  run.material = material.name;
  run.instrument = instrument.name;
  run.vertices = organ.mesh.vertex_count();
  run.triangles = organ.mesh.triangle_count();
  run.rest = motion == SuiteMotion::kRest;
  measure_run(std::move(world), suite_settings(solver.method), duration, run);
  return run;
}

SuiteRun run_suite_case(const SuiteOrgan& organ, SuiteMotion motion, ResponseMethod method) {
  Real duration = 0;
  World world = suite_world(organ, motion, duration);
  SuiteRun run;
  run.organ = organ.name;
  run.source = organ.source;
  run.motion = suite_motion_name(motion);
  run.solver = response_method_name(method);
  run.integrator = integrator_name(IntegratorKind::kImplicitEuler);
  run.method = response_method_name(method);
  run.material = "preset";
  run.instrument = motion == SuiteMotion::kGraspLift ? "grasper" : "hook";
  run.vertices = organ.mesh.vertex_count();
  run.triangles = organ.mesh.triangle_count();
  run.rest = motion == SuiteMotion::kRest;
  measure_run(std::move(world), suite_settings(method), duration, run);
  return run;
}

}  // namespace trocar
