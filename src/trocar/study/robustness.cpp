#include "trocar/study/robustness.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "trocar/core/error.h"
#include "trocar/mesh/instruments.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/organ_shapes.h"
#include "trocar/mesh/renumber.h"
#include "trocar/mesh/repair.h"
#include "trocar/sim/simulation.h"
#include "trocar/tissue/material.h"

namespace trocar {
namespace {

constexpr Real kPressSpeed = 0.02;     ///< m/s, the press and the grasp's approach
constexpr Real kSlideSpeed = 0.04;     ///< m/s (the issue's 40 mm/s)
constexpr Real kSlideLength = 0.02;    ///< m
constexpr Real kApproach = 0.005;      ///< m above the top where every motion starts
constexpr Real kMaxPress = 0.008;      ///< m
constexpr Real kPressFraction = 0.2;   ///< of the local thickness
constexpr Real kFixedFraction = 0.2;   ///< bottom share of the organ's height held fixed

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

/// The p-quantile (nearest rank) of v; 0 when empty.
template <typename T>
T quantile(std::vector<T> v, double p) {
  if (v.empty()) return T{};
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  return v[std::min(k == 0 ? 0 : k - 1, v.size() - 1)];
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
  }
  return "press";
}

std::vector<SuiteMotion> all_suite_motions() {
  return {SuiteMotion::kPress, SuiteMotion::kSlide,    SuiteMotion::kPokeSlow,
          SuiteMotion::kPoke,  SuiteMotion::kPokeFast, SuiteMotion::kGraspLift};
}

Real suite_motion_speed(SuiteMotion motion) {
  switch (motion) {
    case SuiteMotion::kSlide: return kSlideSpeed;
    case SuiteMotion::kPokeSlow: return 0.2;
    case SuiteMotion::kPoke: return 1.0;
    case SuiteMotion::kPokeFast: return 2.0;
    case SuiteMotion::kPress:
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

World suite_world(const SuiteOrgan& organ, SuiteMotion motion, Real& duration) {
  World world;
  const Aabb box = Aabb::of_points(organ.mesh.positions);
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, box.min.z() + kFixedFraction * box.size().z()), Vec3::UnitZ()};
  const MassSpringMaterial material = material_preset(organ.preset);
  const std::vector<std::uint32_t> order = locality_vertex_order(organ.mesh);
  world.add_tissue(organ.name, renumber_vertices(organ.mesh, order), material, fixed, Vec3(0, 0, -9.81),
                   IntegratorKind::kImplicitEuler);

  const OrganTarget target = organ_target(organ.mesh);
  const Vec3 above = target.top + Vec3(0, 0, kApproach);
  const Vec3 pressed = target.top - Vec3(0, 0, target.press_depth);
  std::vector<Keyframe> keys(1);
  keys[0].position = above;
  hold(keys, 0.05);
  Instrument instrument;
  if (motion == SuiteMotion::kGraspLift) {
    const InstrumentMesh grasper = make_grasper();
    instrument = Instrument(grasper.mesh);
    instrument.set_jaw_triangles(grasper.jaw_triangles);
    const Vec3 bite = target.top - Vec3(0, 0, std::min(Real{0.002}, target.press_depth));
    go(keys, bite, kPressSpeed);
    hold(keys, 0.1, 1.0);
    go(keys, bite + Vec3(0, 0, 0.01), kPressSpeed);
    hold(keys, 0.1);
  } else {
    instrument = Instrument(make_hook_probe().mesh);
    switch (motion) {
      case SuiteMotion::kPress:
        go(keys, pressed, kPressSpeed);
        hold(keys, 0.3);
        break;
      case SuiteMotion::kSlide:
        go(keys, pressed, kPressSpeed);
        hold(keys, 0.2);
        go(keys, pressed + kSlideLength * target.slide_direction, kSlideSpeed);
        hold(keys, 0.1);
        break;
      default:
        go(keys, pressed, suite_motion_speed(motion));
        hold(keys, 0.2);
        break;
    }
  }
  duration = keys.back().t;
  world.add_instrument(motion == SuiteMotion::kGraspLift ? "grasper" : "probe",
                       std::move(instrument), KeyframeMotion(std::move(keys)));
  return world;
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

SuiteRun run_suite_case(const SuiteOrgan& organ, SuiteMotion motion, ResponseMethod method) {
  Real duration = 0;
  World world = suite_world(organ, motion, duration);
  Simulation sim(std::move(world), suite_settings(method));
  SuiteRun run;
  run.organ = organ.name;
  run.source = organ.source;
  run.motion = suite_motion_name(motion);
  run.method = response_method_name(method);
  run.vertices = organ.mesh.vertex_count();
  run.triangles = organ.mesh.triangle_count();
  constexpr Real dt = 0.001;
  run.steps = static_cast<std::size_t>(std::ceil(duration / dt - 1e-9));
  std::vector<double> step_us, deform_us, deform_contact_ns, projection_us;
  std::vector<Real> depths;
  step_us.reserve(run.steps);
  deform_us.reserve(run.steps);
  double cg_sum = 0, cg_contact_sum = 0;
  const double per_vertex = 1e3 / static_cast<double>(std::max<std::size_t>(run.vertices, 1));
  for (std::size_t s = 0; s < run.steps; ++s) {
    const StepMetrics& m = sim.step(dt);
    step_us.push_back(m.timings.step - m.timings.metrics);
    deform_us.push_back(m.timings.deformation);
    cg_sum += m.cg_iterations;
    run.cg_max = std::max(run.cg_max, m.cg_iterations);
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
    if (!m.finite) {
      run.stable = false;
      break;
    }
  }
  run.step_median_us = quantile(step_us, 0.5);
  run.step_p99_us = quantile(step_us, 0.99);
  run.deform_median_us = quantile(deform_us, 0.5);
  run.deform_p99_us = quantile(deform_us, 0.99);
  run.deform_ns_per_vertex_contact = quantile(deform_contact_ns, 0.5);
  run.projection_median_us = quantile(projection_us, 0.5);
  run.cg_mean = step_us.empty() ? 0 : cg_sum / static_cast<double>(step_us.size());
  run.cg_mean_contact = run.contact_steps == 0 ? 0 : cg_contact_sum / static_cast<double>(run.contact_steps);
  run.penetration_p99 = quantile(depths, 0.99);
  return run;
}

}  // namespace trocar
