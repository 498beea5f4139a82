#include "trocar/scene/scene.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "trocar/core/error.h"
#include "trocar/core/pose.h"
#include "trocar/mesh/renumber.h"
#include "trocar/mesh/repair.h"
#include "trocar/scene/action_keys.h"
#include "trocar/scene/electrosurgery_keys.h"
#include "trocar/scene/anatomy_scene.h"
#include "trocar/scene/contact_keys.h"
#include "trocar/scene/json_reader.h"
#include "trocar/scene/mesh_source.h"
#include "trocar/scene/task_keys.h"
#include "trocar/tissue/material.h"

namespace trocar {
namespace {

/// "mesh", "scale", "translate", "rotate_deg", "repair" of any object: the mesh with
/// x ↦ translate + R·(scale·x) applied (docs/scene.md "Meshes").
TriMesh placed_mesh(const JsonReader& obj, const std::filesystem::path& dir) {
  TriMesh mesh = load_mesh_source(obj.at("mesh"), dir);
  const Real scale = obj.has("scale") ? obj.at("scale").number_above(0) : 1.0;
  const Pose place = Pose::from_euler_deg(obj.vec3_or("translate", Vec3::Zero()), obj.vec3_or("rotate_deg", Vec3::Zero()));
  for (Vec3& p : mesh.positions) {
    p = place.apply(scale * p);
    // Each factor is finite, but their product or sum can overflow (scale 1e308 of a 2 m box).
    if (!p.allFinite()) obj.fail("the placed mesh has a non-finite vertex position (scale or translate too large)");
  }
  for (Vec3& n : mesh.normals) n = place.apply_vector(n);
  if (obj.boolean_or("repair", false)) repair(mesh);
  if (mesh.empty()) obj.at("mesh").fail("the mesh has no triangles");
  return mesh;
}

std::string name_or(const JsonReader& obj, const char* prefix, std::size_t index) {
  return obj.string_or("name", prefix + std::to_string(index));
}

MassSpringMaterial read_material(const JsonReader& m) {
  m.expect_keys({"preset", "mass", "density", "sheet_thickness", "k_structural", "k_bending", "damping",
                 "spring_damping", "k_area", "k_volume", "k_home", "home_yield"});
  MassSpringMaterial out;
  if (m.has("preset")) {
    const JsonReader p = m.at("preset");
    const std::string name = p.string();
    try {
      out = material_preset(name);
    } catch (const Error& e) {
      p.fail(e.what());
    }
  }
  const auto field = [&](const char* key, Real& value) {
    if (m.has(key)) value = m.at(key).number_at_least(0);
  };
  field("mass", out.mass);
  field("density", out.density);
  field("sheet_thickness", out.sheet_thickness);
  field("k_structural", out.k_structural);
  field("k_bending", out.k_bending);
  field("damping", out.damping);
  field("spring_damping", out.spring_damping);
  field("k_area", out.k_area);
  field("k_volume", out.k_volume);
  field("k_home", out.k_home);
  field("home_yield", out.home_yield);
  return out;
}

FixedSelection read_fixed(const JsonReader& f, std::size_t vertex_count) {
  f.expect_keys({"indices", "below_plane", "inside_box"});
  FixedSelection out;
  if (f.has("indices")) {
    const JsonReader list = f.at("indices");
    for (std::size_t i = 0; i < list.array_size(); ++i)
      out.indices.push_back(static_cast<std::uint32_t>(
          list.at(i).integer(0, static_cast<std::int64_t>(vertex_count) - 1)));
  }
  if (f.has("below_plane")) {
    const JsonReader p = f.at("below_plane");
    p.expect_keys({"point", "normal"});
    Plane plane{p.at("point").vec3(), p.at("normal").vec3()};
    if (plane.normal.norm() == 0) p.at("normal").fail("must not be zero");
    out.below_plane = plane;
  }
  if (f.has("inside_box")) {
    const JsonReader b = f.at("inside_box");
    b.expect_keys({"min", "max"});
    Aabb box{b.at("min").vec3(), b.at("max").vec3()};
    if ((box.min.array() > box.max.array()).any()) b.at("max").fail("must be >= min on every axis");
    out.inside_box = box;
  }
  return out;
}

IntegratorKind read_integrator(const JsonReader& obj) {
  // xpbd by default: of the solvers, the one within the contact targets on the most suite cells
  // at the lowest step cost (docs/robustness.md).
  if (!obj.has("integrator")) return IntegratorKind::kXpbd;
  const JsonReader r = obj.at("integrator");
  const std::string name = r.string();
  try {
    return integrator_from_name(name);
  } catch (const Error& e) {
    r.fail(e.what());
  }
}

void read_tissue(const JsonReader& t, std::size_t index, Scene& scene, const std::filesystem::path& dir) {
  t.expect_keys({"name", "mesh", "scale", "translate", "rotate_deg", "repair", "material", "fixed", "integrator",
                 "substeps", "texture", "appearance", "roll", "lay_on", "graspable", "enters_at", "thermal",
                 "coagulation_stiffening", "bleeds", "tear_force"});
  const std::string name = name_or(t, "tissue", index);
  TriMesh file_mesh = placed_mesh(t, dir);
  if (t.has("lay_on")) read_tissue_lay_on(t.at("lay_on"), scene.world, file_mesh.positions);  // contact_keys.h
  const MassSpringMaterial material = t.has("material") ? read_material(t.at("material")) : MassSpringMaterial{};
  FixedSelection fixed = t.has("fixed") ? read_fixed(t.at("fixed"), file_mesh.vertex_count()) : FixedSelection{};
  const IntegratorKind kind = read_integrator(t);
  int substeps = 0;  // 0: the solver's default
  if (t.has("substeps")) {
    const JsonReader r = t.at("substeps");
    if (kind != IntegratorKind::kXpbd) r.fail("applies to the xpbd integrator only");
    substeps = static_cast<int>(r.integer(1, 64));
  }
  try {
    // The tissue's vertices are renumbered for memory locality (mesh/renumber.h: its steps run
    // 3-5 % faster); `fixed.indices` name vertices in the file's order, so they follow.
    const std::vector<std::uint32_t> order = locality_vertex_order(file_mesh);
    const TriMesh mesh = renumber_vertices(file_mesh, order);
    const std::vector<std::uint32_t> new_index = inverse_order(order);
    for (std::uint32_t& v : fixed.indices) v = new_index[v];
    TissueBody& tissue = scene.world.add_tissue(name, mesh, material, fixed, scene.gravity, kind);
    if (substeps > 0) tissue.integrator.xpbd()->set_substeps(substeps);
  } catch (const Error& e) {
    t.fail(e.what());
  }
  if (t.has("roll")) read_tissue_roll(t.at("roll"), *scene.world.tissues.back());  // contact_keys.h
  if (t.has("graspable")) scene.world.tissues.back()->graspable = t.at("graspable").boolean();
  if (t.has("enters_at")) scene.world.tissues.back()->enters_at = t.at("enters_at").number_at_least(0);
  if (t.has("thermal")) scene.world.tissues.back()->thermal = read_thermal(t.at("thermal"));  // electrosurgery_keys.h
  if (t.has("bleeds")) scene.world.tissues.back()->bleeds = read_vessel(t.at("bleeds"));
  if (t.has("tear_force")) scene.world.tissues.back()->tear_force = t.at("tear_force").number_at_least(0);
  if (t.has("coagulation_stiffening"))
    scene.world.tissues.back()->coagulation_stiffening = t.at("coagulation_stiffening").number_above(0);
  std::filesystem::path texture;
  if (t.has("texture")) {
    const JsonReader tex = t.at("texture");
    texture = dir / tex.string();
    if (!std::filesystem::is_regular_file(texture)) tex.fail(texture.string() + ": no such image");
    if (file_mesh.texcoords.empty()) tex.fail("the mesh has no texture coordinates (OBJ vt, PLY u/v) to map it with");
  }
  scene.textures.push_back(std::move(texture));
  scene.tissue_appearance.push_back(t.has("appearance") ? read_appearance(t.at("appearance")) : Appearance{});
}

KeyframeMotion read_motion(const JsonReader& m) {
  m.expect_keys({"keyframes", "interpolation"});
  Interpolation interpolation = Interpolation::kLinear;
  if (m.has("interpolation")) {
    const JsonReader i = m.at("interpolation");
    const std::string name = i.string();
    if (name == "smooth") interpolation = Interpolation::kSmooth;
    else if (name != "linear") i.fail("unknown interpolation \"" + name + "\" (known: linear, smooth)");
  }
  const JsonReader list = m.at("keyframes");
  std::vector<Keyframe> keys;
  for (std::size_t i = 0; i < list.array_size(); ++i) {
    const JsonReader k = list.at(i);
    k.expect_keys({"t", "position", "rotate_deg", "jaw"});
    Keyframe key;
    key.t = k.at("t").number_at_least(0);
    if (!keys.empty() && !(key.t > keys.back().t)) k.at("t").fail("must be greater than the previous keyframe's t");
    key.position = k.at("position").vec3();
    // The motion interpolates between neighbours: their difference must be finite too.
    if (!keys.empty() && !(key.position - keys.back().position).allFinite())
      k.at("position").fail("too far from the previous keyframe's position (the motion between them overflows)");
    key.rotation = Pose::from_euler_deg(Vec3::Zero(), k.vec3_or("rotate_deg", Vec3::Zero())).rotation;
    if (k.has("jaw")) {
      key.jaw = k.at("jaw").number_at_least(0);
      if (key.jaw > 1) k.at("jaw").fail("must be <= 1");
    }
    keys.push_back(key);
  }
  if (keys.empty()) list.fail("must hold at least one keyframe");
  return KeyframeMotion(std::move(keys), interpolation);
}

DeviceSpec read_device(const JsonReader& d, const std::filesystem::path& dir) {
  d.expect_keys({"driver", "port", "recording", "translate", "rotate_deg", "scale", "coupling", "max_force",
                 "slew_rate", "engage_below", "ramp_time", "damping", "stale_after", "pivot", "force_scale"});
  DeviceSpec s;
  s.given = true;
  s.where = d.file() + ": " + d.path();
  const JsonReader driver = d.at("driver");
  s.driver = driver.string();
  if (s.driver != "null" && s.driver != "scripted" && s.driver != "replay" && s.driver != "openigtlink" &&
      s.driver != "spacemouse" && s.driver != "mouse")
    driver.fail("unknown driver \"" + s.driver + "\" (known: null, scripted, replay, openigtlink, spacemouse, mouse)");
  if (d.has("pivot")) {
    if (s.driver != "mouse") d.at("pivot").fail("only the mouse driver pivots about a port");
    s.has_pivot = true;
    s.pivot = d.at("pivot").vec3();
  }
  if (d.has("port")) s.port = static_cast<int>(d.at("port").integer(0, 65535));
  if (s.driver == "replay") {
    const JsonReader rec = d.at("recording");
    s.recording = dir / rec.string();
  } else if (d.has("recording")) {
    d.at("recording").fail("only the replay driver reads a recording");
  }
  s.device_to_world = Pose::from_euler_deg(d.vec3_or("translate", Vec3::Zero()), d.vec3_or("rotate_deg", Vec3::Zero()));
  if (d.has("scale")) s.scale = d.at("scale").number_above(0);
  if (d.has("coupling")) {
    const JsonReader c = d.at("coupling");
    c.expect_keys({"stiffness", "damping"});
    if (c.has("stiffness")) s.coupling_stiffness = c.at("stiffness").number_at_least(0);
    if (c.has("damping")) s.coupling_damping = c.at("damping").number_at_least(0);
  }
  if (d.has("max_force")) s.max_force = d.at("max_force").number_at_least(0);
  if (d.has("force_scale")) s.force_scale = d.at("force_scale").number_at_least(0);
  if (d.has("slew_rate")) s.slew_rate = d.at("slew_rate").number_above(0);
  if (d.has("engage_below")) s.engage_below = d.at("engage_below").number_above(0);
  if (d.has("ramp_time")) s.ramp_time = d.at("ramp_time").number_at_least(0);
  if (d.has("damping")) s.damping = d.at("damping").number_at_least(0);
  if (d.has("stale_after")) s.stale_after = d.at("stale_after").number_above(0);
  return s;
}

void read_instrument(const JsonReader& r, std::size_t index, Scene& scene, const std::filesystem::path& dir) {
  r.expect_keys({"name", "mesh", "scale", "translate", "rotate_deg", "repair", "top_vertex", "shaft_direction",
                 "jaw_triangles", "motion", "device", "port", "electrode", "suction"});
  const std::string name = name_or(r, "instrument", index);
  TriMesh mesh = placed_mesh(r, dir);
  const std::size_t nv = mesh.vertex_count();
  const std::size_t nt = mesh.triangle_count();
  Instrument instrument(std::move(mesh), r.vec3_or("shaft_direction", Vec3::Zero()));
  if (r.has("top_vertex")) {
    const JsonReader top = r.at("top_vertex");
    if (top.is_string()) {
      if (top.string() != "auto") top.fail("must be \"auto\" or a vertex index");
    } else {
      instrument.set_top_vertex(static_cast<std::uint32_t>(top.integer(0, static_cast<std::int64_t>(nv) - 1)));
    }
  }
  if (r.has("jaw_triangles")) {
    const JsonReader list = r.at("jaw_triangles");
    std::vector<std::uint32_t> tris;
    for (std::size_t i = 0; i < list.array_size(); ++i)
      tris.push_back(static_cast<std::uint32_t>(list.at(i).integer(0, static_cast<std::int64_t>(nt) - 1)));
    instrument.set_jaw_triangles(tris);
  }
  DeviceSpec device;
  if (r.has("device")) device = read_device(r.at("device"), dir);
  KeyframeMotion motion = r.has("motion") ? read_motion(r.at("motion")) : KeyframeMotion{};
  InstrumentBody& body = scene.world.add_instrument(name, std::move(instrument), std::move(motion));
  if (r.has("port")) body.port = r.at("port").string();
  const JsonReader source = r.at("mesh");
  if (source.is_object() && source.has("generate")) body.tool = source.at("generate").string();
  if (r.has("electrode")) body.electrode = read_electrode(r.at("electrode"));  // electrosurgery_keys.h
  // A suction-irrigator only with the key, as an electrode (SuctionSpec's own defaults are a live one).
  body.suction = r.has("suction") ? read_suction(r.at("suction")) : SuctionSpec::none();
  scene.devices.push_back(std::move(device));
}

/// "ports": {name: [x, y, z] or a landmark's name}: where each named port enters the body
/// (docs/scene.md, the root key "ports"). Every instrument naming that port takes the point
/// (Instrument::set_port).
void read_ports(const JsonReader& ports, Scene& scene) {
  if (!ports.is_object()) ports.fail("must be an object of port name: [x, y, z] or a landmark's name");
  for (const auto& item : ports.value().items()) {
    const JsonReader at = ports.at(item.key());
    Vec3 point;
    if (at.is_string()) {
      const auto found = scene.landmarks.find(at.string());
      if (found == scene.landmarks.end())
        at.fail("the scene has no landmark \"" + at.string() + "\" (give it in \"landmarks\" or with the anatomy)");
      point = found->second;
    } else {
      point = at.vec3();
    }
    bool named = false;
    for (InstrumentBody& body : scene.world.instruments)
      if (body.port == item.key()) {
        body.instrument.set_port(point);
        named = true;
      }
    if (!named) at.fail("no instrument enters through port \"" + item.key() + "\" (an instrument's \"port\")");
  }
}

void read_rigid(const JsonReader& r, std::size_t index, Scene& scene, const std::filesystem::path& dir) {
  r.expect_keys({"name", "mesh", "scale", "translate", "rotate_deg", "repair", "appearance"});
  scene.world.add_rigid(name_or(r, "rigid", index), placed_mesh(r, dir));
  scene.rigid_appearance.push_back(r.has("appearance") ? read_appearance(r.at("appearance")) : Appearance{});
}

void read_collision(const JsonReader& c, Scene& scene) {
  c.expect_keys({"broad_phase", "cell_size", "period"});
  SimulationSettings& s = scene.settings;
  if (c.has("broad_phase")) {
    const JsonReader b = c.at("broad_phase");
    const std::string name = b.string();
    if (name == "ohc") s.broad_phase = BroadPhaseKind::kOhc;
    else if (name == "bvh") s.broad_phase = BroadPhaseKind::kBvh;
    else if (name == "brute") s.broad_phase = BroadPhaseKind::kBruteForce;
    else b.fail("unknown broad phase \"" + name + "\" (known: ohc, bvh, brute)");
  }
  if (c.has("cell_size")) {
    const JsonReader cs = c.at("cell_size");
    if (cs.is_string()) {
      if (cs.string() != "auto") cs.fail("must be \"auto\" or a number > 0");
      s.cell_size = 0;
    } else {
      s.cell_size = cs.number_above(0);
    }
  }
  if (c.has("period")) s.collision_period = c.at("period").number_above(0);
}

void read_response(const JsonReader& r, Scene& scene) {
  r.expect_keys({"method", "stiffness", "damping", "max_force", "resting_speed", "grasp_closure", "pierce_filter",
                 "depth_cap", "correction_speed", "contact_margin", "friction_static", "friction_kinetic", "projection_rounds"});
  ResponseSettings& s = scene.settings.response;
  if (r.has("method")) {
    const JsonReader m = r.at("method");
    const std::string name = m.string();
    const auto method = parse_response_method(name);
    if (!method) m.fail("unknown method \"" + name + "\" (known: sdf, obb, primitive, normal, project)");
    s.method = *method;
  }
  if (r.has("stiffness")) s.stiffness = r.at("stiffness").number_at_least(0);
  if (r.has("damping")) s.damping = r.at("damping").number_at_least(0);
  if (r.has("max_force")) s.max_force = r.at("max_force").number();
  if (r.has("resting_speed")) s.resting_speed = r.at("resting_speed").number_at_least(0);
  if (r.has("grasp_closure")) {
    s.grasp_closure = r.at("grasp_closure").number_at_least(0);
    if (s.grasp_closure > 1) r.at("grasp_closure").fail("must be <= 1");
  }
  if (r.has("pierce_filter")) s.pierce_filter = r.at("pierce_filter").boolean();
  if (r.has("depth_cap")) s.depth_cap = r.at("depth_cap").boolean();
  if (r.has("correction_speed")) s.correction_speed = r.at("correction_speed").number_at_least(0);
  if (r.has("contact_margin")) s.contact_margin = r.at("contact_margin").number_at_least(0);
  if (r.has("friction_static")) s.friction_static = r.at("friction_static").number_at_least(0);
  if (r.has("friction_kinetic")) s.friction_kinetic = r.at("friction_kinetic").number_at_least(0);
  if (r.has("projection_rounds")) s.projection_rounds = static_cast<int>(r.at("projection_rounds").integer(1, 100));
}

CameraSpec read_camera(const JsonReader& c, std::size_t index) {
  c.expect_keys({"name", "type", "port", "target", "insertion", "angle_deg", "roll_deg", "up", "fov_deg", "distance",
                 "yaw_deg", "pitch_deg", "near", "far"});
  CameraSpec s;
  s.name = c.string_or("name", index == 0 ? "scope" : "camera" + std::to_string(index));
  const std::string type = c.string_or("type", "laparoscope");
  if (type == "laparoscope") s.kind = CameraKind::kLaparoscope;
  else if (type == "orbit") s.kind = CameraKind::kOrbit;
  else c.at("type").fail("unknown camera type \"" + type + "\" (known: laparoscope, orbit)");
  s.target = c.vec3_or("target", s.target);
  s.up = c.vec3_or("up", s.up);
  if (s.up.norm() < 1e-12) c.at("up").fail("must not be zero");
  s.up.normalize();
  if (c.has("fov_deg")) {
    s.fov_deg = c.at("fov_deg").number_above(0);
    if (s.fov_deg >= 170) c.at("fov_deg").fail("must be < 170");
  }
  if (c.has("near")) s.near_clip = c.at("near").number_above(0);
  if (c.has("far")) s.far_clip = c.at("far").number_above(s.near_clip);
  if (s.kind == CameraKind::kLaparoscope) {
    for (const char* key : {"distance", "yaw_deg", "pitch_deg"})
      if (c.has(key)) c.at(key).fail("only an orbit camera has it");
    s.port = c.at("port").vec3();
    if ((s.target - s.port).norm() < 1e-9) c.at("target").fail("must differ from the port");
    if (c.has("insertion")) s.insertion = c.at("insertion").number_at_least(0);
    if (c.has("angle_deg")) {
      s.angle_deg = c.at("angle_deg").number_at_least(0);
      if (s.angle_deg > 90) c.at("angle_deg").fail("must be <= 90");
    }
    if (c.has("roll_deg")) s.roll_deg = c.at("roll_deg").number();
  } else {
    for (const char* key : {"port", "insertion", "angle_deg", "roll_deg"})
      if (c.has(key)) c.at(key).fail("only a laparoscope has it");
    if (c.has("distance")) s.distance = c.at("distance").number_above(0);
    if (c.has("yaw_deg")) s.yaw_deg = c.at("yaw_deg").number();
    if (c.has("pitch_deg")) {
      s.pitch_deg = c.at("pitch_deg").number();
      if (std::abs(s.pitch_deg) >= 90) c.at("pitch_deg").fail("must be in (-90, 90)");
    }
  }
  return s;
}

void read_cameras(const JsonReader& c, Scene& scene) {
  if (c.is_object()) {
    scene.cameras.push_back(read_camera(c, 0));
    return;
  }
  for (std::size_t i = 0; i < c.array_size(); ++i) {
    scene.cameras.push_back(read_camera(c.at(i), i));
    for (std::size_t j = 0; j < i; ++j)
      if (scene.cameras[j].name == scene.cameras[i].name)
        c.at(i).at("name").fail("camera name \"" + scene.cameras[i].name + "\" is used twice");
  }
}

}  // namespace

Scene parse_scene(std::string_view text, const std::string& file, const std::filesystem::path& dir) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(file + ": byte " + std::to_string(e.byte) + ": invalid JSON");
  } catch (const nlohmann::json::exception& e) {
    // A number beyond double's range (out_of_range 406): its text, without the library's prefix.
    const std::string what = e.what();
    throw Error(file + ": invalid JSON: " + what.substr(what.find("] ") == std::string::npos ? 0 : what.find("] ") + 2));
  }
  const JsonReader root(doc, file);
  root.expect_keys({"schema", "name", "timestep", "duration", "gravity", "tissues", "instruments", "rigids",
                    "collision", "response", "camera", "events", "anatomy", "tissue_contacts", "zones",
                    "landmarks", "task", "tissue_coupling", "ports"});
  Scene scene;
  root.at("schema").integer(kSceneSchema, kSceneSchema);
  scene.name = root.string_or("name", std::filesystem::path(file).stem().string());
  if (root.has("timestep")) scene.timestep = root.at("timestep").number_above(0);
  if (root.has("duration")) scene.duration = root.at("duration").number_at_least(0);
  scene.gravity = root.vec3_or("gravity", scene.gravity);
  scene.settings.collision_period = scene.timestep;
  if (root.has("collision")) read_collision(root.at("collision"), scene);
  if (root.has("response")) read_response(root.at("response"), scene);
  const auto each = [&](const char* key, auto read) {
    if (!root.has(key)) return;
    const JsonReader list = root.at(key);
    for (std::size_t i = 0; i < list.array_size(); ++i) read(list.at(i), i, scene, dir);
  };
  if (root.has("anatomy")) read_anatomy(root.at("anatomy"), scene);  // its tissues and rigids come first
  each("tissues", read_tissue);
  each("instruments", read_instrument);
  each("rigids", read_rigid);
  if (root.has("tissue_contacts")) read_tissue_contacts(root.at("tissue_contacts"), scene);  // contact_keys.h
  if (root.has("tissue_coupling")) read_tissue_coupling(root.at("tissue_coupling"), scene);
  if (root.has("camera")) read_cameras(root.at("camera"), scene);
  if (root.has("events")) scene.actions = read_actions(root.at("events"), scene.world);
  // The real-time runtime presses them as buttons: a short press each, but the held ones (the
  // electrode's pedal, the suction and irrigation valves) are held from their on to the
  // instrument's next matching off (or the end); an off is that release, no button of its own.
  for (std::size_t k = 0; k < scene.actions.size(); ++k) {
    const ScriptedAction& a = scene.actions[k];
    if (a.instrument >= scene.devices.size() || (a.action & (kHeldActions << 1)) != 0) continue;
    double until = -1;
    if (a.action & kHeldActions) {
      const std::uint32_t release = a.action << 1;  // actions.h: each held action's Off bit
      until = std::numeric_limits<double>::infinity();
      for (const ScriptedAction& off : scene.actions)
        if (off.instrument == a.instrument && off.action == release && off.t >= a.t) until = std::min(until, off.t);
    }
    scene.devices[a.instrument].presses.push_back({a.t, a.action << 1, until});
  }
  read_task_keys(root, scene);  // the task's names are checked against everything above
  if (root.has("ports")) read_ports(root.at("ports"), scene);  // after the landmarks it may name
  return scene;
}

std::string read_scene_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Scene load_scene(const std::filesystem::path& file) {
  return parse_scene(read_scene_text(file), file.string(), file.parent_path());
}

}  // namespace trocar
