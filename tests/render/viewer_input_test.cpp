// The viewer's event mapping (render/viewer_input.h), its event scripts, and the panel's scene edits.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "trocar/core/error.h"
#include "trocar/render/viewer_input.h"
#include "trocar/render/viewer_panel.h"
#include "trocar/scene/scene.h"
#include "trocar/tissue/material.h"

namespace trocar {
namespace {

TEST(ViewerInput, LeftDragPivotsRightDragRollsAndInsertsWheelInserts) {
  ViewerInput in;
  in.mouse_button(0, true, 100, 100);
  in.cursor(150, 80);
  in.mouse_button(0, false, 150, 80);
  EXPECT_NEAR(in.command().yaw, -50 * ViewerInput::kRadiansPerPixel, 1e-12);
  EXPECT_NEAR(in.command().pitch, -20 * ViewerInput::kRadiansPerPixel, 1e-12);
  EXPECT_TRUE(in.take_changed());
  EXPECT_FALSE(in.take_changed());
  in.cursor(300, 300);  // no button: nothing moves
  EXPECT_FALSE(in.take_changed());
  in.mouse_button(1, true, 300, 300);
  in.cursor(310, 290);
  EXPECT_NEAR(in.command().roll, 10 * ViewerInput::kRollPerPixel, 1e-12);
  EXPECT_NEAR(in.command().depth, 10 * ViewerInput::kDepthPerPixel, 1e-12);
  in.mouse_button(1, false, 310, 290);
  in.scroll(-1);
  EXPECT_NEAR(in.command().depth, 10 * ViewerInput::kDepthPerPixel - ViewerInput::kDepthPerNotch, 1e-12);
  in.mouse_button(0, true, 0, 0, /*over_panel=*/true);  // the panel's click
  in.cursor(100, 0);
  EXPECT_NEAR(in.command().yaw, -50 * ViewerInput::kRadiansPerPixel, 1e-12);
}

TEST(ViewerInput, KeysMoveWhileHeldJawWhileHeldAndOneShotsFireOnce) {
  ViewerInput in;
  in.key(ViewerKey::kInsert, true);
  in.advance(0.5);
  in.key(ViewerKey::kInsert, false);
  in.advance(0.5);
  EXPECT_NEAR(in.command().depth, 0.05 * ViewerInput::kKeyRate * 0.5, 1e-12);
  in.key(ViewerKey::kJaw, true);
  EXPECT_EQ(in.command().jaw, 1);
  in.key(ViewerKey::kJaw, false);
  EXPECT_EQ(in.command().jaw, 0);
  EXPECT_EQ(in.key(ViewerKey::kPause, true), ViewerKey::kPause);
  EXPECT_EQ(in.key(ViewerKey::kPause, true), ViewerKey::kOther);  // auto-repeat
  EXPECT_FALSE(in.free_camera);
  in.key(ViewerKey::kToggleCamera, true);
  EXPECT_TRUE(in.free_camera);
  // In free-camera mode a left drag orbits the camera, not the instrument.
  in.orbit.yaw_deg = 0;
  const double yaw = in.command().yaw;
  in.mouse_button(0, true, 0, 0);
  in.cursor(10, 0);
  EXPECT_EQ(in.command().yaw, yaw);
  EXPECT_NEAR(in.orbit.yaw_deg, -3, 1e-12);
}

TEST(ViewerInput, FireAndExchangeKeysHoldTheDeviceButtonsTheRuntimeActsOn) {
  ViewerInput in;
  EXPECT_EQ(in.key(ViewerKey::kFire, true), ViewerKey::kOther);  // not a one-shot of the viewer's own
  EXPECT_EQ(in.command().buttons, 1u << 1);                       // button 1: fire (procedure/actions.h)
  in.key(ViewerKey::kExchange, true);
  EXPECT_EQ(in.command().buttons, (1u << 1) | (1u << 2));          // button 2: exchange
  in.key(ViewerKey::kFire, false);
  EXPECT_EQ(in.command().buttons, 1u << 2);
  in.key(ViewerKey::kExchange, false);
  EXPECT_EQ(in.command().buttons, 0u);
  EXPECT_EQ(viewer_key_from_name("fire"), ViewerKey::kFire);
  EXPECT_EQ(viewer_key_from_name("exchange"), ViewerKey::kExchange);
}

TEST(ViewerInput, HeldValveKeysHoldButtonsFiveAndSeven) {
  ViewerInput in;
  EXPECT_EQ(in.key(ViewerKey::kSuction, true), ViewerKey::kOther);
  EXPECT_EQ(in.command().buttons, 1u << 5);  // button 5: suction (procedure/actions.h)
  in.key(ViewerKey::kIrrigate, true);
  EXPECT_EQ(in.command().buttons, (1u << 5) | (1u << 7));  // button 7: irrigation
  in.key(ViewerKey::kEnergy, true);
  EXPECT_EQ(in.command().buttons, (1u << 3) | (1u << 5) | (1u << 7));  // button 3: the pedal
  in.key(ViewerKey::kSuction, false);
  EXPECT_EQ(in.command().buttons, (1u << 3) | (1u << 7));
  in.key(ViewerKey::kIrrigate, false);
  in.key(ViewerKey::kEnergy, false);
  EXPECT_EQ(in.command().buttons, 0u);
  EXPECT_EQ(viewer_key_from_name("suction"), ViewerKey::kSuction);
  EXPECT_EQ(viewer_key_from_name("irrigate"), ViewerKey::kIrrigate);
  EXPECT_EQ(viewer_key_from_name("energy"), ViewerKey::kEnergy);
}

TEST(ViewerInput, ScriptsAreReadAndBadLinesNamed) {
  const auto file = std::filesystem::temp_directory_path() / "trocar_events_test.txt";
  {
    std::ofstream f(file);
    f << "# a drag\n0.5 down 0 10 20\n0.6 move 30 20\n\n0.7 up 0 30 20\n0.8 key jaw\n0.9 keyup jaw\n1 scroll -2\n";
  }
  const auto events = read_injected_events(file.string());
  ASSERT_EQ(events.size(), 6u);
  EXPECT_EQ(events[3].key, ViewerKey::kJaw);
  EXPECT_EQ(events[5].y, -2);
  const auto fails = [&](const char* text, const char* says) {
    { std::ofstream f(file); f << "0.1 move 1 1\n" << text << "\n"; }
    try {
      read_injected_events(file.string());
      ADD_FAILURE() << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  fails("0.2 jump", ":2: unknown event");
  fails("0.2 key fly", ":2: unknown key");
  fails("0.05 move 1 1", ":2: times must not decrease");
  fails("0.2 down 7 1 1", ":2: down needs");
  fails("soon move 1 1", ":2: expected a time");
  fails("f3 move 1 1", ":2: times must be all seconds or all frames");
  std::filesystem::remove(file);
}

TEST(ViewerInput, FrameScriptsNameTheFrameBeforeWhichEachEventPlays) {
  const auto file = std::filesystem::temp_directory_path() / "trocar_frame_events_test.txt";
  {
    std::ofstream f(file);
    f << "f0 down 0 10 20\nf2 move 30 20\nf2 up 0 30 20\nf5 settle  # the runtime takes it in\n";
  }
  const auto events = read_injected_events(file.string());
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0].frame, 0);
  EXPECT_EQ(events[2].frame, 2);
  EXPECT_EQ(events[3].frame, 5);
  EXPECT_EQ(events[3].kind, "settle");
  const auto fails = [&](const char* text, const char* says) {
    { std::ofstream f(file); f << "f1 move 1 1\n" << text << "\n"; }
    try {
      read_injected_events(file.string());
      ADD_FAILURE() << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  fails("f0 move 1 1", ":2: times must not decrease");
  fails("f1.5 move 1 1", ":2: expected a time in seconds or a frame fN");
  fails("fx move 1 1", ":2: expected a time");
  fails("0.5 move 1 1", ":2: times must be all seconds or all frames");
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace trocar


namespace trocar {
namespace {

TEST(ViewerPanel, EditsStartFromTheSceneAndApplyAsAValidScene) {
  std::ifstream in(std::string(TROCAR_TEST_SCENES) + "/hernia.json");
  nlohmann::json doc = nlohmann::json::parse(in);
  SceneEdits e = edits_from(doc, 0);
  ASSERT_EQ(e.tissues.size(), 1u);
  const MassSpringMaterial peritoneum = material_preset("peritoneum");
  EXPECT_FLOAT_EQ(e.tissues[0].k_structural, float(peritoneum.k_structural));  // the preset's value
  EXPECT_EQ(e.tissues[0].integrator, 3);    // xpbd
  EXPECT_EQ(e.method, 0);                   // obb
  EXPECT_FLOAT_EQ(e.stiffness, 500);
  EXPECT_FLOAT_EQ(e.timestep, 0.001f);
  e.tissues[0].k_structural = 1234;
  e.method = 1;        // sdf
  e.broad_phase = 1;   // bvh
  e.timestep = 0.002f;
  apply_edits(doc, e, 0);
  const Scene scene = parse_scene(doc.dump(), "edited.json", TROCAR_TEST_SCENES);
  EXPECT_EQ(scene.settings.response.method, ResponseMethod::kSdf);
  EXPECT_EQ(scene.settings.broad_phase, BroadPhaseKind::kBvh);
  EXPECT_NEAR(scene.timestep, 0.002, 1e-9);
  EXPECT_NEAR(scene.settings.collision_period, 0.002, 1e-9);
  EXPECT_NEAR(scene.world.tissues[0]->settings.springs[0].stiffness, 1234, 1e-3);
  EXPECT_EQ(edits_from(doc, 0).tissues[0].k_structural, 1234);
}

}  // namespace
}  // namespace trocar
