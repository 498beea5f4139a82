// Scene keys "zones", "landmarks" and "task": values read, every key checked, names resolved.
#include <gtest/gtest.h>

#include <string>

#include "procedure/task_scene.h"
#include "trocar/core/error.h"

namespace trocar {
namespace {

/// The error text parsing `extra` gives ("" when it parses).
std::string error_of(const std::string& extra) {
  try {
    test::task_scene(extra);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(TaskKeys, ReadsEveryValue) {
  const Scene scene = test::task_scene(R"("zones": [{"name": "doom", "depth": 0.003,
      "polygon": [[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0]]}],
    "task": {"name": "TAPP", "sac": "sac", "mesh": "mesh", "vessels": ["wall"], "wall_tissue": "wall",
             "reduced_fraction": 0.8, "overlap": 0.025, "defect_radius": 0.012, "coverage_spacing": 0.002,
             "max_fold_area": 1e-4, "min_tacks": 5, "tack_landmarks": ["tack_cooper", "tack_medial"],
             "tack_radius": 0.01, "tack_reach": 0.0015, "tack_pullout": 22.7, "zone_force": 2.0,
             "zone_release": 0.2, "drop_distance": 0.05})");
  ASSERT_EQ(scene.zones.size(), 1u);
  EXPECT_EQ(scene.zones[0].name, "doom");
  EXPECT_EQ(scene.zones[0].depth, 0.003);
  EXPECT_EQ(scene.zones[0].polygon.size(), 3u);
  EXPECT_EQ(scene.landmarks.at("tack_lateral"), Vec3(0, 0.02, 0));
  ASSERT_TRUE(scene.task.has_value());
  const TaskSpec& t = *scene.task;
  EXPECT_EQ(t.name, "TAPP");
  EXPECT_EQ(t.sac, "sac");
  EXPECT_EQ(t.mesh, "mesh");
  ASSERT_EQ(t.vessels.size(), 1u);
  EXPECT_EQ(t.vessels[0], "wall");
  EXPECT_EQ(t.wall_tissue, "wall");
  EXPECT_EQ(t.reduced_fraction, 0.8);
  EXPECT_EQ(t.overlap, 0.025);
  EXPECT_EQ(t.defect_radius, 0.012);
  EXPECT_EQ(t.coverage_spacing, 0.002);
  EXPECT_EQ(t.max_fold_area, 1e-4);
  EXPECT_EQ(t.min_tacks, 5);
  EXPECT_EQ(t.tack_landmarks.size(), 2u);
  EXPECT_EQ(t.tack_radius, 0.01);
  EXPECT_EQ(t.tack_reach, 0.0015);
  EXPECT_EQ(t.tack_pullout, 22.7);
  EXPECT_EQ(t.zone_force, 2.0);
  EXPECT_EQ(t.zone_release, 0.2);
  EXPECT_EQ(t.drop_distance, 0.05);
}

TEST(TaskKeys, DefaultsAreTheDocumentedRules) {
  const Scene scene = test::task_scene();
  const TaskSpec& t = *scene.task;
  EXPECT_EQ(t.reduced_fraction, 0.9);
  EXPECT_EQ(t.overlap, 0.03);
  EXPECT_EQ(t.max_fold_area, 2e-4);
  EXPECT_EQ(t.min_tacks, 4);
  EXPECT_EQ(t.tack_landmarks, (std::vector<std::string>{"tack_cooper", "tack_medial", "tack_lateral"}));
  EXPECT_EQ(t.tack_radius, 0.015);
  EXPECT_EQ(t.tack_reach, 0.002);
  EXPECT_EQ(t.tack_pullout, 28.6);
  EXPECT_EQ(t.zone_force, 1.5);
  EXPECT_FALSE(test::task_scene("").task.has_value());
}

TEST(TaskKeys, BadValuesFailNamingTheirKey) {
  EXPECT_NE(error_of(R"("task": {"sac": "bowel", "mesh": "mesh"})").find("task.sac: no tissue named \"bowel\""),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "vessels": ["wall", "artery"]})")
                .find("task.vessels[1]: no tissue named \"artery\""),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "wall_tissue": "x"})").find("task.wall_tissue"),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"mesh": "mesh"})").find("task.sac: missing"), std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "colour": 1})").find("task.colour: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "sac"})").find("task.mesh"), std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "reduced_fraction": 1.5})").find("task.reduced_fraction"),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "zone_force": 0})").find("task.zone_force"),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "min_tacks": 2.5})").find("task.min_tacks"),
            std::string::npos);
  EXPECT_NE(error_of(R"("task": {"sac": "sac", "mesh": "mesh", "tack_landmarks": ["tack_cooper", "pubis"]})")
                .find("task.tack_landmarks[1]: the scene has no landmark \"pubis\""),
            std::string::npos);
  EXPECT_NE(error_of(R"("zones": [{"name": "z", "polygon": [[0, 0, 0], [1, 0, 0]]}])").find("zones[0].polygon"),
            std::string::npos);
  EXPECT_NE(error_of(R"("zones": [{"name": "z", "polygon": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}])").find("collinear"),
            std::string::npos);
  EXPECT_NE(error_of(R"("zones": [{"name": "z", "polygon": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "depth": -1}])")
                .find("zones[0].depth"),
            std::string::npos);
  EXPECT_NE(error_of(R"("zones": [{"name": "z", "polygon": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "size": 1}])")
                .find("zones[0].size: unknown key"),
            std::string::npos);
}

TEST(TaskKeys, MissingWallLandmarksFail) {
  // The scene's landmarks without "wall_normal": a task cannot be tested.
  std::string text = test::task_scene_text(R"("task": {"sac": "sac", "mesh": "mesh"})");
  const std::string key = R"("wall_normal": [0, 0, 1], )";
  text.erase(text.find(key), key.size());
  try {
    parse_scene(text, "t.json", ".");
    FAIL() << "parsed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no landmark \"wall_normal\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trocar
