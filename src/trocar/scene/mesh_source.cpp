#include "trocar/scene/mesh_source.h"

#include <atomic>
#include <system_error>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/scene/anatomy_generators.h"
#include "trocar/scene/contact_keys.h"

namespace trocar {
namespace {

std::size_t count(const JsonReader& spec, std::string_view key, std::int64_t fallback, std::int64_t min,
                  std::int64_t max) {
  return static_cast<std::size_t>(spec.has(key) ? spec.at(key).integer(min, max) : fallback);
}

TriMesh icosphere(const JsonReader& spec) {
  spec.expect_keys({"generate", "radius", "subdivisions"});
  return make_icosphere(spec.at("radius").number_above(0), static_cast<int>(count(spec, "subdivisions", 3, 0, 7)));
}

TriMesh sheet(const JsonReader& spec) {
  spec.expect_keys({"generate", "width", "height", "nx", "ny", "bulge_height"});
  return make_sheet(spec.at("width").number_above(0), spec.at("height").number_above(0),
                    count(spec, "nx", 16, 1, 1000), count(spec, "ny", 16, 1, 1000),
                    spec.number_or("bulge_height", 0));
}

TriMesh capsule(const JsonReader& spec) {
  spec.expect_keys({"generate", "radius", "length", "segments", "rings"});
  return make_capsule(spec.at("radius").number_above(0), spec.at("length").number_at_least(0),
                      count(spec, "segments", 16, 3, 1000), count(spec, "rings", 4, 1, 1000));
}

TriMesh cylinder(const JsonReader& spec) {
  spec.expect_keys({"generate", "radius", "length", "segments", "capped"});
  return make_cylinder(spec.at("radius").number_above(0), spec.at("length").number_above(0),
                       count(spec, "segments", 16, 3, 1000), spec.boolean_or("capped", true));
}

TriMesh box(const JsonReader& spec) {
  spec.expect_keys({"generate", "size"});
  const Vec3 size = spec.at("size").vec3();
  if ((size.array() <= 0).any()) spec.at("size").fail("every size must be > 0");
  return make_box(size.x(), size.y(), size.z());
}

}  // namespace

const std::vector<MeshGenerator>& mesh_generators() {
  static const std::vector<MeshGenerator> table = {
      {"icosphere", icosphere, "radius (m, required), subdivisions (0..7, default 3)"},
      {"sheet", sheet, "width, height (m, required), nx, ny (cells, default 16), bulge_height (m, default 0)"},
      {"capsule", capsule, "radius, length (m, required), segments (default 16), rings (default 4)"},
      {"cylinder", cylinder, "radius, length (m, required), segments (default 16), capped (default true)"},
      {"box", box, "size [x, y, z] (m, required)"},
      // Procedural anatomy and instruments (scene/anatomy_generators.h lists their keys).
      {"hernia-peritoneum", generate_hernia_peritoneum, "width, height, sac_radius, sac_depth (m); segments, sac_rings, sheet_rings"},
      {"abdominal-wall", generate_abdominal_wall, "width, height, hole_radius (m); thickness (m, 0 = sheet); segments, rings"},
      {"liver-lobe", generate_liver_lobe, "length, width, thickness (m); subdivisions, flatten, taper"},
      {"grasper", generate_grasper, "all optional (5 mm grasper): shaft_radius, shaft_length, jaw_* (m), segments; jaw triangles 0..23"},
      // A clip applier is drawn and collides as a grasper (its jaws); "fire" clips the bleeding
      // point between them (Simulation::clip_at).
      {"clip-applier", generate_grasper, "as grasper (a 5 mm clip applier: its fire clips the wound at its tip)"},
      {"prosthetic-mesh", generate_prosthetic_mesh, "width, height (m, required), spacing (m, default 0.005); UVs in metres"},
      {"hook-probe", generate_hook_probe, "all optional (4.5 mm hook): shaft_radius, shaft_length, hook_radius, stem_length, hook_length (m), segments"},
      {"tacker", generate_tacker, "all optional (5 mm tack applier): shaft_radius, shaft_length, bevel (m), segments"},
      {"suction-irrigator", generate_suction_irrigator, "all optional (5 mm suction-irrigation cannula): shaft_radius, shaft_length, tip_round (m), round_rings, segments"},
  };
  return table;
}

TriMesh make_generated_mesh(const JsonReader& spec) {
  const JsonReader kind = spec.at("generate");
  const std::string name = kind.string();
  std::string names;
  for (const MeshGenerator& g : mesh_generators()) {
    if (name == g.name) return g.make(spec);
    names += (names.empty() ? "" : ", ") + std::string(g.name);
  }
  kind.fail("unknown generator \"" + name + "\" (known: " + names + ")");
}

namespace {
std::atomic<VolumeMeshBuilder> volume_builder{nullptr};
}  // namespace

void set_volume_mesh_builder(VolumeMeshBuilder builder) { volume_builder.store(builder); }

TriMesh load_mesh_source(const JsonReader& mesh, const std::filesystem::path& scene_dir) {
  if (mesh.is_object() && mesh.has("build")) {
    const VolumeMeshBuilder builder = volume_builder.load();
    if (builder == nullptr) {
      mesh.at("build").fail("this trocar was built without the modelling module, so it cannot build a mesh from a "
                            "volume (install libvtk9-dev and libinsighttoolkit5-dev and rebuild: docs/build.md), or "
                            "build it with `trocar mesh build` and name the mesh file");
    }
    return builder(mesh, scene_dir);
  }
  if (mesh.is_object()) return make_generated_mesh(mesh);
  if (!mesh.is_string()) mesh.fail("must be a file path, an object {\"generate\": ...} or {\"build\": VOLUME, ...}");
  const std::filesystem::path path = scene_dir / mesh.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) mesh.fail("file not found: " + path.string());
  try {
    return load_mesh(path);
  } catch (const Error& e) {
    mesh.fail(e.what());
  }
}

}  // namespace trocar
