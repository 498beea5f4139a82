// The scene key "anatomy" (tapp-inguinal) and the per-object "appearance" (scene/anatomy_scene.h).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "trocar/core/error.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

Scene parse(const std::string& body) {
  return parse_scene("{\"schema\": 1, " + body + "}", "test.json", ".");
}

void expect_error(const std::string& body, const std::string& needle) {
  try {
    parse(body);
    ADD_FAILURE() << "no error for " << body;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(AnatomyScene, ExpandsIntoTissuesRigidsZonesLandmarksAndAppearances) {
  const Scene s = parse(R"("anatomy": {"generate": "tapp-inguinal", "hernia": "indirect"})");
  ASSERT_EQ(s.world.tissues.size(), 13u);
  ASSERT_EQ(s.world.rigids.size(), 1u);
  EXPECT_EQ(s.world.rigids[0].name, "pubic_bone");
  EXPECT_EQ(s.tissue_appearance.size(), 13u);
  EXPECT_EQ(s.rigid_appearance.size(), 1u);
  EXPECT_EQ(s.textures.size(), 13u);
  EXPECT_EQ(s.world.tissues[0]->name, "abdominal_wall");
  EXPECT_TRUE(s.tissue_appearance[0].given);
  EXPECT_LT(s.tissue_appearance[1].opacity, 1.0f);  // the peritoneum is translucent
  EXPECT_EQ(s.zones.size(), 4u);
  for (const char* name : {"defect_centre", "wall_point", "wall_normal", "tack_cooper", "camera_port", "mesh_start"})
    EXPECT_EQ(s.landmarks.count(name), 1u) << name;
  // Cooper's ligament: every vertex fixed (renumbering keeps the count).
  for (const auto& t : s.world.tissues)
    if (t->name == "coopers_ligament") {
      for (std::uint8_t f : t->settings.fixed) EXPECT_EQ(f, 1);
    }
}

TEST(AnatomyScene, DirectVariantAndAppearanceKey) {
  const Scene s = parse(R"("anatomy": {"generate": "tapp-inguinal", "hernia": "direct", "tube_segments": 8},
    "rigids": [{"name": "box", "mesh": {"generate": "box", "size": [0.01, 0.01, 0.01]},
                "appearance": {"colour": [0.1, 0.2, 0.3], "opacity": 0.5, "pattern": "weave"}}])");
  ASSERT_EQ(s.rigid_appearance.size(), 2u);
  EXPECT_FLOAT_EQ(s.rigid_appearance[1].colour[2], 0.3f);
  EXPECT_EQ(s.rigid_appearance[1].pattern, SurfacePattern::kWeave);
  EXPECT_GT(s.landmarks.at("defect_centre").x(), 0.0);
}

TEST(AnatomyScene, BadKeysNameTheKey) {
  expect_error(R"("anatomy": {"generate": "tapp", "hernia": "direct"})", "anatomy.generate");
  expect_error(R"("anatomy": {"generate": "tapp-inguinal", "hernia": "femoral"})", "anatomy.hernia");
  expect_error(R"("anatomy": {"generate": "tapp-inguinal"})", "hernia");
  expect_error(R"("anatomy": {"generate": "tapp-inguinal", "hernia": "direct", "cell": 1})", "anatomy.cell");
  expect_error(R"("anatomy": {"generate": "tapp-inguinal", "hernia": "direct", "sac_segments": 10})", "sac_segments");
  expect_error(R"("anatomy": {"generate": "tapp-inguinal", "hernia": "direct", "colour": 1})", "colour");
  expect_error(R"("rigids": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.01]}, "appearance": {"opacity": 2}}])",
               "appearance.opacity");
  expect_error(R"("rigids": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.01]}, "appearance": {"pattern": "x"}}])",
               "appearance.pattern");
  expect_error(R"("rigids": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.01]}, "appearance": {"colour": [2, 0, 0]}}])",
               "appearance.colour");
}

}  // namespace
}  // namespace trocar
