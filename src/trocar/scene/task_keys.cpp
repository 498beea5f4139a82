#include "trocar/scene/task_keys.h"

#include <string>

namespace trocar {
namespace {

NamedZone read_zone(const JsonReader& z) {
  z.expect_keys({"name", "polygon", "depth"});
  NamedZone zone;
  zone.name = z.at("name").string();
  if (zone.name.empty()) z.at("name").fail("must not be empty");
  const JsonReader poly = z.at("polygon");
  if (poly.array_size() < 3) poly.fail("needs at least 3 corners");
  for (std::size_t i = 0; i < poly.array_size(); ++i) zone.polygon.push_back(poly.at(i).vec3());
  if (zone.normal().isZero()) poly.fail("the corners must span a plane (they are collinear or repeated)");
  if (z.has("depth")) zone.depth = z.at("depth").number_above(0);
  return zone;
}

void read_landmarks(const JsonReader& l, Scene& scene) {
  if (!l.is_object()) l.fail("must be an object of name: [x, y, z]");
  for (const auto& item : l.value().items()) scene.landmarks[item.key()] = l.at(item.key()).vec3();
}

void require_tissue(const JsonReader& key, const Scene& scene) {
  const std::string name = key.string();
  for (const auto& t : scene.world.tissues)
    if (t->name == name) return;
  key.fail("no tissue named \"" + name + "\"");
}

void require_landmark(const JsonReader& at, const Scene& scene, const std::string& name) {
  if (scene.landmarks.count(name) == 0)
    at.fail("the scene has no landmark \"" + name + "\" (give it in \"landmarks\" or with the anatomy)");
}

TaskSpec read_task(const JsonReader& t, const Scene& scene) {
  t.expect_keys({"name", "sac", "mesh", "vessels", "wall_tissue", "reduced_fraction", "overlap", "defect_radius",
                 "coverage_spacing", "max_fold_area", "min_tacks", "tack_landmarks", "tack_radius", "tack_reach",
                 "tack_pullout", "zone_force", "zone_release", "drop_distance"});
  TaskSpec s;
  s.name = t.string_or("name", s.name);
  require_tissue(t.at("sac"), scene);
  s.sac = t.at("sac").string();
  require_tissue(t.at("mesh"), scene);
  s.mesh = t.at("mesh").string();
  if (s.mesh == s.sac) t.at("mesh").fail("must not be the sac's tissue");
  if (t.has("vessels")) {
    const JsonReader v = t.at("vessels");
    for (std::size_t i = 0; i < v.array_size(); ++i) {
      require_tissue(v.at(i), scene);
      s.vessels.push_back(v.at(i).string());
    }
  }
  if (t.has("wall_tissue")) {
    require_tissue(t.at("wall_tissue"), scene);
    s.wall_tissue = t.at("wall_tissue").string();
  }
  if (t.has("reduced_fraction")) {
    s.reduced_fraction = t.at("reduced_fraction").number_above(0);
    if (s.reduced_fraction > 1) t.at("reduced_fraction").fail("must be <= 1");
  }
  const auto at_least = [&](const char* key, Real& value, Real min) {
    if (t.has(key)) value = t.at(key).number_at_least(min);
  };
  const auto above = [&](const char* key, Real& value, Real min) {
    if (t.has(key)) value = t.at(key).number_above(min);
  };
  at_least("overlap", s.overlap, 0);
  at_least("defect_radius", s.defect_radius, 0);
  above("coverage_spacing", s.coverage_spacing, 0);
  at_least("max_fold_area", s.max_fold_area, 0);
  if (t.has("min_tacks")) s.min_tacks = static_cast<int>(t.at("min_tacks").integer(0, 1000));
  if (t.has("tack_landmarks")) {
    s.tack_landmarks.clear();
    const JsonReader l = t.at("tack_landmarks");
    for (std::size_t i = 0; i < l.array_size(); ++i) s.tack_landmarks.push_back(l.at(i).string());
  }
  above("tack_radius", s.tack_radius, 0);
  above("tack_reach", s.tack_reach, 0);
  above("tack_pullout", s.tack_pullout, 0);
  above("zone_force", s.zone_force, 0);
  at_least("zone_release", s.zone_release, 0);
  above("drop_distance", s.drop_distance, 0);

  // The landmarks the tests read must be in the scene.
  for (const char* name : {"wall_point", "wall_normal", "defect_centre"}) require_landmark(t, scene, name);
  if (scene.landmarks.at("wall_normal").norm() <= 0) t.fail("the landmark \"wall_normal\" must not be zero");
  for (std::size_t i = 0; i < s.tack_landmarks.size(); ++i)
    require_landmark(t.has("tack_landmarks") ? t.at("tack_landmarks").at(i) : t, scene, s.tack_landmarks[i]);
  if (scene.landmarks.count("mpo_0") != 0 && (scene.landmarks.count("mpo_1") == 0 || scene.landmarks.count("mpo_2") == 0))
    t.fail("the MPO needs at least 3 corners (landmarks mpo_0, mpo_1, mpo_2, ...)");
  return s;
}

}  // namespace

void read_task_keys(const JsonReader& root, Scene& scene) {
  if (root.has("zones")) {
    const JsonReader z = root.at("zones");
    for (std::size_t i = 0; i < z.array_size(); ++i) scene.zones.push_back(read_zone(z.at(i)));
  }
  if (root.has("landmarks")) read_landmarks(root.at("landmarks"), scene);
  if (root.has("task")) scene.task = read_task(root.at("task"), scene);
}

}  // namespace trocar
