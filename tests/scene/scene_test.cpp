// Scene files: a valid scene loads into a World; each kind of error names the file and key path.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

/// A minimal valid scene with one generated tissue and one generated instrument; `tissue_extra`
/// and `top_extra` are spliced into the tissue object and the root object.
std::string scene_text(const std::string& tissue_extra = "", const std::string& top_extra = "") {
  return R"({"schema": 1, "timestep": 0.001,)" + top_extra + R"(
    "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 2},
                 "material": {"preset": "liver", "k_area": 10})" + tissue_extra + R"(}],
    "instruments": [{"mesh": {"generate": "cylinder", "radius": 0.002, "length": 0.05},
                     "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.05]}]}}]})";
}

/// The message of the error parse_scene throws for `text` ("" when none).
std::string error_of(const std::string& text, const std::filesystem::path& dir = ".") {
  try {
    parse_scene(text, "scene.json", dir);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, ValidSceneBuildsTheWorld) {
  const Scene scene = parse_scene(scene_text(R"(, "fixed": {"below_plane": {"point": [0,0,-0.02], "normal": [0,0,1]}})",
                                             R"( "name": "t", "collision": {"broad_phase": "bvh", "cell_size": 0.004, "period": 0.002},
                                                 "response": {"method": "project", "stiffness": 100, "depth_cap": false,
                                                              "correction_speed": 0.2},)"),
                                  "scene.json", ".");
  EXPECT_EQ(scene.name, "t");
  ASSERT_EQ(scene.world.tissues.size(), 1u);
  EXPECT_EQ(scene.world.tissues[0]->name, "ball");
  EXPECT_EQ(scene.world.tissues[0]->settings.vertex_count(), 162u);
  EXPECT_EQ(scene.world.tissues[0]->settings.k_area, 10.0);  // preset overridden
  ASSERT_EQ(scene.world.instruments.size(), 1u);
  EXPECT_EQ(scene.world.instruments[0].name, "instrument0");
  EXPECT_NEAR(scene.world.instruments[0].thickness, 0.004, 1e-3);
  EXPECT_EQ(scene.settings.broad_phase, BroadPhaseKind::kBvh);
  EXPECT_EQ(scene.settings.cell_size, 0.004);
  EXPECT_EQ(scene.settings.collision_period, 0.002);
  EXPECT_EQ(scene.settings.response.method, ResponseMethod::kProject);
  EXPECT_EQ(scene.settings.response.stiffness, 100.0);
  EXPECT_FALSE(scene.settings.response.depth_cap);
  EXPECT_EQ(scene.settings.response.correction_speed, 0.2);
  const Scene plain = parse_scene(scene_text(), "scene.json", ".");
  EXPECT_TRUE(plain.settings.response.depth_cap);                 // the default
  EXPECT_EQ(plain.settings.response.correction_speed, 0.05);      // the default (m/s)
}

// The loader renumbers a tissue's vertices for locality (mesh/renumber.h); fixed.indices name
// vertices of the file, so the vertices fixed are the ones at those file positions.
TEST(Scene, FixedIndicesFollowTheRenumberedVertices) {
  const TriMesh file_mesh = make_icosphere(0.03, 2);
  const Scene scene = parse_scene(scene_text(R"(, "fixed": {"indices": [0, 5, 161]})"), "scene.json", ".");
  const MassSpringSettings& s = scene.world.tissues[0]->settings;
  ASSERT_EQ(s.vertex_count(), file_mesh.vertex_count());
  std::vector<Vec3> fixed_positions;
  for (std::size_t v = 0; v < s.vertex_count(); ++v)
    if (s.fixed[v]) fixed_positions.push_back(s.rest_positions[v]);
  ASSERT_EQ(fixed_positions.size(), 3u);
  for (const std::uint32_t v : {0u, 5u, 161u})
    EXPECT_NE(std::find(fixed_positions.begin(), fixed_positions.end(), file_mesh.positions[v]),
              fixed_positions.end())
        << "file vertex " << v;
  // And the renumbering did happen: the icosphere generator's own order is not local.
  EXPECT_NE(s.rest_positions[0], file_mesh.positions[0]);
}

TEST(Scene, UnknownKeyNamesItsPath) {
  EXPECT_EQ(error_of(scene_text(R"(, "colour": "red")")).rfind("scene.json: tissues[0].colour: unknown key", 0), 0u)
      << error_of(scene_text(R"(, "colour": "red")"));
}

TEST(Scene, WrongTypeNamesItsPath) {
  EXPECT_EQ(error_of(scene_text("", R"( "timestep": "fast",)")), "scene.json: timestep: must be a number, not a string");
  EXPECT_EQ(error_of(scene_text("", R"( "response": {"depth_cap": 1},)")),
            "scene.json: response.depth_cap: must be a boolean, not a number");
}

TEST(Scene, MissingFileNamesTheKeyAndThePath) {
  const std::string text = R"({"schema": 1, "tissues": [{"mesh": "no/such.obj"}]})";
  const std::string e = error_of(text, "/tmp");
  EXPECT_EQ(e.rfind("scene.json: tissues[0].mesh: file not found: /tmp/no/such.obj", 0), 0u) << e;
}

TEST(Scene, BadValueNamesItsPath) {
  const std::string text = R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.03},
                                "material": {"k_area": -1}}]})";
  EXPECT_EQ(error_of(text), "scene.json: tissues[0].material.k_area: must be >= 0");
  EXPECT_EQ(error_of(scene_text("", R"( "response": {"correction_speed": -0.1},)")),
            "scene.json: response.correction_speed: must be >= 0");
}

TEST(Scene, UnknownPresetIntegratorMethodGeneratorAndBroadPhase) {
  EXPECT_NE(error_of(R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.03},
                        "material": {"preset": "granite"}}]})").find("scene.json: tissues[0].material.preset: "),
            std::string::npos);
  EXPECT_NE(error_of(R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.03},
                        "integrator": "rk4"}]})").find("scene.json: tissues[0].integrator: "),
            std::string::npos);
  EXPECT_EQ(error_of(R"({"schema": 1, "response": {"method": "magic"}})"),
            "scene.json: response.method: unknown method \"magic\" (known: sdf, obb, primitive, normal, project)");
  EXPECT_EQ(error_of(R"({"schema": 1, "collision": {"broad_phase": "grid"}})"),
            "scene.json: collision.broad_phase: unknown broad phase \"grid\" (known: ohc, bvh, brute)");
  EXPECT_EQ(error_of(R"({"schema": 1, "tissues": [{"mesh": {"generate": "torus"}}]})")
                .rfind("scene.json: tissues[0].mesh.generate: unknown generator \"torus\"", 0),
            0u);
  EXPECT_EQ(error_of(R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0}}]})"),
            "scene.json: tissues[0].mesh.radius: must be > 0");
}

TEST(Scene, SdfResponseKeys) {
  const Scene s = parse_scene(R"({"schema": 1, "response": {"method": "sdf", "contact_margin": 0.0001,
                                 "friction_static": 0.3, "friction_kinetic": 0.2, "projection_rounds": 5}})",
                              "scene.json", ".");
  EXPECT_EQ(s.settings.response.method, ResponseMethod::kSdf);
  EXPECT_DOUBLE_EQ(s.settings.response.contact_margin, 0.0001);
  EXPECT_DOUBLE_EQ(s.settings.response.friction_static, 0.3);
  EXPECT_DOUBLE_EQ(s.settings.response.friction_kinetic, 0.2);
  EXPECT_EQ(s.settings.response.projection_rounds, 5);
  EXPECT_EQ(error_of(R"({"schema": 1, "response": {"friction_static": -1}})"),
            "scene.json: response.friction_static: must be >= 0");
  EXPECT_NE(error_of(R"({"schema": 1, "response": {"projection_rounds": 0}})").find("scene.json: response.projection_rounds: "),
            std::string::npos);
}

TEST(Scene, MotionInterpolationIsLinearOrSmooth) {
  const auto motion = [](const std::string& interpolation) {
    return R"({"schema": 1, "instruments": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.1]},
      "motion": {"interpolation": ")" + interpolation + R"(", "keyframes": [{"t": 0, "position": [0, 0, 0]},
        {"t": 1, "position": [0, 0, 0.01]}, {"t": 2, "position": [0, 0, 0.03]}]}}]})";
  };
  const Scene smooth = parse_scene(motion("smooth"), "scene.json", ".");
  EXPECT_EQ(smooth.world.instruments[0].motion.interpolation(), Interpolation::kSmooth);
  // From rest: h01(0.5)·0.01 + h11(0.5)·1·0.015 (the tangent at 1 s, the mean of 0.01 and 0.02 m/s).
  EXPECT_NEAR(smooth.world.instruments[0].motion.sample(0.5).pose.translation.z(), 0.005 - 0.125 * 0.015, 1e-15);
  EXPECT_EQ(parse_scene(motion("linear"), "scene.json", ".").world.instruments[0].motion.interpolation(),
            Interpolation::kLinear);
  EXPECT_EQ(error_of(motion("cubic")),
            "scene.json: instruments[0].motion.interpolation: unknown interpolation \"cubic\" (known: linear, smooth)");
}

TEST(Scene, SchemaKeyframesAndTopVertexAreChecked) {
  EXPECT_EQ(error_of(R"({"tissues": []})"), "scene.json: schema: missing (required)");
  EXPECT_EQ(error_of(R"({"schema": 2})"), "scene.json: schema: must be in [1, 1], not 2");
  EXPECT_EQ(error_of(R"({"schema": 1, "instruments": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.1]},
      "motion": {"keyframes": [{"t": 1, "position": [0,0,0]}, {"t": 1, "position": [0,0,1]}]}}]})"),
            "scene.json: instruments[0].motion.keyframes[1].t: must be greater than the previous keyframe's t");
  EXPECT_EQ(error_of(R"({"schema": 1, "instruments": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.1]},
      "top_vertex": 8}]})"),
            "scene.json: instruments[0].top_vertex: must be in [0, 7], not 8");
  EXPECT_EQ(error_of("{\"schema\": 1,"), "scene.json: byte 14: invalid JSON");
  // A number beyond double's range is a trocar::Error too (fuzz_scene found it escaping).
  EXPECT_EQ(error_of(R"({"schema": 1, "timestep": 2e308})"), "scene.json: invalid JSON: number overflow parsing '2e308'");
}

// Finite factors whose product or sum overflows (fuzz_scene found the first): a 4 m box (corners
// at ±2 m) scaled by 1e308.
TEST(Scene, PlacementOrMotionThatOverflowsIsAnError) {
  EXPECT_EQ(error_of(R"({"schema": 1, "rigids": [{"mesh": {"generate": "box", "size": [4, 1, 1]}, "scale": 1e308}]})"),
            "scene.json: rigids[0]: the placed mesh has a non-finite vertex position (scale or translate too large)");
  EXPECT_EQ(error_of(R"({"schema": 1, "instruments": [{"mesh": {"generate": "box", "size": [1e308, 1, 1]},
                        "translate": [1.7e308, 0, 0]}]})"),
            "scene.json: instruments[0]: the placed mesh has a non-finite vertex position (scale or translate too large)");
  EXPECT_EQ(error_of(R"({"schema": 1, "instruments": [{"mesh": {"generate": "box", "size": [0.01, 0.01, 0.1]},
      "motion": {"keyframes": [{"t": 0, "position": [-1e308, 0, 0]}, {"t": 1, "position": [1e308, 0, 0]}]}}]})"),
            "scene.json: instruments[0].motion.keyframes[1].position: too far from the previous keyframe's position "
            "(the motion between them overflows)");
}

TEST(Scene, MeshPathsAreRelativeToTheSceneFile) {
  const auto dir = std::filesystem::temp_directory_path() / "trocar_scene_test_relative";
  std::filesystem::create_directories(dir / "meshes");
  std::ofstream(dir / "meshes" / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  std::ofstream(dir / "s.json") << R"({"schema": 1, "rigids": [{"name": "table", "mesh": "meshes/tri.obj", "scale": 0.5,
                                     "translate": [0, 0, 1]}]})";
  const Scene scene = load_scene(dir / "s.json");
  ASSERT_EQ(scene.world.rigids.size(), 1u);
  EXPECT_EQ(scene.name, "s");
  EXPECT_EQ(scene.world.rigids[0].mesh.positions[1], Vec3(0.5, 0, 1));
  std::filesystem::remove_all(dir);
}

TEST(Scene, TackerGeneratorBuildsTheFiveMillimetreInstrument) {
  Scene scene = parse_scene(R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.03}}],
    "instruments": [{"mesh": {"generate": "tacker", "segments": 12}, "top_vertex": "auto",
                     "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.05]}]}}]})", "scene.json", ".");
  const TriMesh& m = scene.world.instruments[0].instrument.local_mesh();
  EXPECT_EQ(m.positions.size(), 3u * 12 + 2);
  EXPECT_EQ(m.triangles.size(), 6u * 12);
  Real top = 0;
  for (const Vec3& p : m.positions) top = std::max(top, p.z());
  EXPECT_NEAR(top, 0.33, 1e-12);  // the handle end; the tip at the origin
  EXPECT_NE(error_of(R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.03}}],
    "instruments": [{"mesh": {"generate": "tacker", "bevel": 0.01}}]})").find("tacker bevel"), std::string::npos);
}

// "ports": a port's point, given or a landmark's, goes to every instrument naming that port; an
// unknown landmark, a port no instrument enters through and a bad value are errors naming the key.
TEST(Scene, PortsPlaceWhereTheShaftsEnterTheBody) {
  const std::string two = R"({"schema": 1,
    "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 1}}],
    "instruments": [{"name": "a", "port": "right", "mesh": {"generate": "cylinder", "radius": 0.002, "length": 0.05}},
                    {"name": "b", "port": "right", "mesh": {"generate": "cylinder", "radius": 0.002, "length": 0.05}},
                    {"name": "c", "mesh": {"generate": "cylinder", "radius": 0.002, "length": 0.05}}],
    "landmarks": {"port_right": [0.07, 0.13, 0.05]},)";
  const Scene scene = parse_scene(two + R"( "ports": {"right": "port_right"}})", "scene.json", ".");
  for (const std::size_t i : {0u, 1u}) {
    ASSERT_TRUE(scene.world.instruments[i].instrument.has_port());
    EXPECT_EQ((scene.world.instruments[i].instrument.port() - Vec3(0.07, 0.13, 0.05)).norm(), 0);
  }
  EXPECT_FALSE(scene.world.instruments[2].instrument.has_port());
  const Scene given = parse_scene(two + R"( "ports": {"right": [0.01, 0.02, 0.03]}})", "scene.json", ".");
  EXPECT_EQ((given.world.instruments[1].instrument.port() - Vec3(0.01, 0.02, 0.03)).norm(), 0);
  const Scene none = parse_scene(two + R"( "name": "n"})", "scene.json", ".");
  EXPECT_FALSE(none.world.instruments[0].instrument.has_port());

  EXPECT_NE(error_of(two + R"( "ports": {"right": "port_left"}})").find("ports.right: the scene has no landmark \"port_left\""),
            std::string::npos)
      << error_of(two + R"( "ports": {"right": "port_left"}})");
  EXPECT_NE(error_of(two + R"( "ports": {"left": [0, 0, 0]}})").find("no instrument enters through port \"left\""),
            std::string::npos);
  EXPECT_NE(error_of(two + R"( "ports": {"right": [0, 0]}})").find("ports.right"), std::string::npos);
  EXPECT_NE(error_of(two + R"( "ports": [1, 2, 3]})").find("ports"), std::string::npos);
}

}  // namespace
}  // namespace trocar
