// The laparoscope and orbit cameras (render/camera.h) and the scene's "camera" key.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "trocar/core/error.h"
#include "trocar/scene/camera.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

CameraSpec scope(Real angle_deg, Real roll_deg = 0) {
  CameraSpec s;
  s.port = Vec3(0, 0, 0.2);
  s.target = Vec3(0, 0, 0);
  s.insertion = 0.05;
  s.angle_deg = angle_deg;
  s.roll_deg = roll_deg;
  s.up = Vec3(0, 1, 0);
  s.fov_deg = 60;
  return s;
}

TEST(Camera, ZeroDegreeScopeLooksDownItsShaftFromItsTip) {
  const CameraView v = make_camera_view(scope(0), 4.0 / 3.0);
  EXPECT_NEAR((v.eye - Vec3(0, 0, 0.15)).norm(), 0, 1e-12);
  EXPECT_NEAR((v.forward - Vec3(0, 0, -1)).norm(), 0, 1e-12);
  // The target is on the axis: the image centre, depth inside (0, 1).
  const Eigen::Vector3d c = v.project(Vec3(0, 0, 0), 640, 480);
  EXPECT_NEAR(c.x(), 320, 1e-3);
  EXPECT_NEAR(c.y(), 240, 1e-3);
  EXPECT_GT(c.z(), 0);
  EXPECT_LT(c.z(), 1);
  // A point at the top edge of the 60° field: tan(30°) · distance above the axis, at row 0.
  const Real d = 0.15;
  const Eigen::Vector3d top = v.project(Vec3(0, d * std::tan(std::numbers::pi / 6), 0), 640, 480);
  EXPECT_NEAR(top.y(), 0, 1e-3);
  // +x is to the right when up is +y and the view is −z.
  EXPECT_GT(v.project(Vec3(0.01, 0, 0), 640, 480).x(), 320);
  // Behind the eye: negative depth.
  EXPECT_LT(v.project(Vec3(0, 0, 0.3), 640, 480).z(), 0);
}

TEST(Camera, ThirtyDegreeScopeTiltsItsViewFromTheShaftAndRollTurnsIt) {
  const Vec3 shaft(0, 0, -1);
  const CameraView a = make_camera_view(scope(30), 1.0);
  EXPECT_NEAR(std::acos(a.forward.dot(shaft)) * 180 / std::numbers::pi, 30, 1e-9);
  EXPECT_GT(a.forward.y(), 0.49);  // towards "up" at roll 0: sin 30° = 0.5
  const CameraView b = make_camera_view(scope(30, 180), 1.0);
  EXPECT_NEAR(std::acos(b.forward.dot(shaft)) * 180 / std::numbers::pi, 30, 1e-9);
  EXPECT_LT(b.forward.y(), -0.49);
  EXPECT_NEAR((a.eye - b.eye).norm(), 0, 1e-12);  // rolling turns the lens, not the tip
  EXPECT_NEAR(a.up.dot(a.forward), 0, 1e-12);
}

TEST(Camera, OrbitLooksAtItsTargetFromItsDistance) {
  CameraSpec s;
  s.kind = CameraKind::kOrbit;
  s.target = Vec3(0.1, 0.2, 0.3);
  s.distance = 0.5;
  s.yaw_deg = 40;
  s.pitch_deg = 20;
  const CameraView v = make_camera_view(s, 1.5);
  EXPECT_NEAR((v.eye - s.target).norm(), 0.5, 1e-12);
  EXPECT_NEAR(v.forward.dot((s.target - v.eye).normalized()), 1, 1e-12);
  EXPECT_NEAR(std::asin((v.eye - s.target).normalized().dot(s.up)) * 180 / std::numbers::pi, 20, 1e-9);
}

Scene parse(const std::string& camera) {
  return parse_scene(R"({"schema": 1, "camera": )" + camera + "}", "s.json", ".");
}

TEST(Camera, SceneKeyIsReadAndValidated) {
  const Scene one = parse(R"({"port": [0, 0, 0.2], "target": [0, 0, 0], "angle_deg": 30, "fov_deg": 75})");
  ASSERT_EQ(one.cameras.size(), 1u);
  EXPECT_EQ(one.cameras[0].name, "scope");
  EXPECT_EQ(one.cameras[0].angle_deg, 30);
  const Scene two = parse(R"([{"name": "a", "port": [0, 0, 1], "target": [0, 0, 0]},
                              {"name": "b", "type": "orbit", "distance": 0.3}])");
  ASSERT_EQ(two.cameras.size(), 2u);
  EXPECT_EQ(two.cameras[1].kind, CameraKind::kOrbit);
  const auto fails = [](const std::string& camera, const std::string& says) {
    try {
      parse(camera);
      ADD_FAILURE() << camera << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  fails(R"({"port": [0, 0, 1], "target": [0, 0, 0], "zoom": 2})", "zoom");
  fails(R"({"target": [0, 0, 0]})", "camera.port");
  fails(R"({"port": [0, 0, 0], "target": [0, 0, 0]})", "camera.target");
  fails(R"({"port": [0, 0, 1], "target": [0, 0, 0], "fov_deg": 180})", "camera.fov_deg");
  fails(R"({"type": "fisheye", "port": [0, 0, 1]})", "camera.type");
  fails(R"({"type": "orbit", "port": [0, 0, 1]})", "only a laparoscope");
  fails(R"([{"name": "a", "type": "orbit"}, {"name": "a", "type": "orbit"}])", "camera[1].name");
}

}  // namespace
}  // namespace trocar
