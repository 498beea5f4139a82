// `trocar view` under Xvfb (skipped only when Xvfb cannot start) and `trocar run --frames/--video`.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "support/run_program.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using trocar::test::run_program;

/// An Xvfb server on a free display for the test's lifetime.
class Xvfb {
 public:
  Xvfb() {
    for (int n = 100 + int(getpid() % 300); n < 1000 && pid_ == 0; n += 7) {
      if (fs::exists("/tmp/.X11-unix/X" + std::to_string(n)) || fs::exists("/tmp/.X" + std::to_string(n) + "-lock"))
        continue;
      const std::string display = ":" + std::to_string(n);
      const char* argv[] = {"Xvfb", display.c_str(), "-screen", "0", "1280x800x24", "-nolisten", "tcp", nullptr};
      posix_spawn_file_actions_t actions;
      posix_spawn_file_actions_init(&actions);
      posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
      pid_t pid = 0;
      const int rc = posix_spawnp(&pid, "Xvfb", &actions, nullptr, const_cast<char* const*>(argv), environ);
      posix_spawn_file_actions_destroy(&actions);
      if (rc != 0) return;  // not installed
      for (int i = 0; i < 100; ++i) {  // up to 5 s for the socket
        if (fs::exists("/tmp/.X11-unix/X" + std::to_string(n))) {
          pid_ = pid;
          display_ = display;
          return;
        }
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) break;  // it died (display taken): try the next
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (pid_ == 0) {
        kill(pid, SIGTERM);
        waitpid(pid, nullptr, 0);
      }
    }
  }
  ~Xvfb() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  bool running() const { return pid_ > 0; }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = 0;
  std::string display_;
};

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

/// Width and height from a PNG's IHDR chunk.
std::pair<int, int> png_size(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  const auto be = [&](int o) { return (h[o] << 24) | (h[o + 1] << 16) | (h[o + 2] << 8) | h[o + 3]; };
  if (h[1] != 'P' || h[2] != 'N' || h[3] != 'G') return {0, 0};
  return {be(16), be(20)};
}

fs::path temp(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("trocar_view_test_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d / name;
}

const std::string kScenes = TROCAR_SCENES_DIR;

TEST(ViewCli, OpensUnderXvfbRunsTwoSecondsAndTakesAScreenshot) {
  Xvfb x;
  if (!x.running()) GTEST_SKIP() << "Xvfb cannot start here";
  const fs::path shot = temp("shot.png"), report = temp("view.json");
  const auto r = run_program("DISPLAY=" + x.display() + " " TROCAR_CLI,
                             "view " + kScenes + "/hernia.json --quit-after 2 --screenshot " + shot.string() +
                                 " --report " + report.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(png_size(shot), std::make_pair(1280, 720));
  const nlohmann::json j = read_json(report);
  EXPECT_GE(j["frames"].get<int>(), 1);
  EXPECT_GE(j["wall_time_s"].get<double>(), 2.0);
  // The haptic loop and physics ran with the window open (their rates beside rendering are
  // bench_render's and bench_runtime's to measure, not a test's on a shared machine).
  EXPECT_GT(j["haptic"]["ticks"].get<int>(), 0);
  EXPECT_GT(j["physics"]["steps"].get<int>(), 0);
  // The screenshot is not blank: a flat image compresses to far less.
  EXPECT_GT(fs::file_size(shot), 20000u);
}

TEST(ViewCli, InjectedMouseDragPivotsTheInstrumentAboutItsPort) {
  Xvfb x;
  if (!x.running()) GTEST_SKIP() << "Xvfb cannot start here";
  const fs::path events = temp("events.txt"), report = temp("drag.json");
  {
    std::ofstream e(events);
    // Events between frames, then "settle": the runtime takes them in (counted ticks and steps).
    e << "# left drag 100 px right, 50 px down: yaw -0.4 rad, pitch +0.2 rad\n"
         "f2 move 800 400\nf3 down 0 800 400\nf4 move 850 425\nf5 move 900 450\nf6 up 0 900 450\n"
         "f7 scroll 2   # 4 mm deeper\nf8 settle\n";
  }
  const auto r = run_program("DISPLAY=" + x.display() + " " TROCAR_CLI,
                             "view " + kScenes + "/probe_press_slide.json --no-panel --quit-after-frames 10 --inject " +
                                 events.string() + " --report " + report.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = read_json(report);
  const nlohmann::json& d = j["driven_instrument"];
  EXPECT_EQ(j["frames"].get<int>(), 10);
  EXPECT_EQ(j["events_played"].get<int>(), 7);
  EXPECT_EQ(d["device"].get<std::string>(), "mouse (port pivot)");
  EXPECT_NEAR(d["command"]["yaw"].get<double>(), -0.4, 1e-9);
  EXPECT_NEAR(d["command"]["pitch"].get<double>(), 0.2, 1e-9);
  EXPECT_NEAR(d["command"]["depth"].get<double>(), 0.004, 1e-9);
  // The probe starts at (0, 0, 0.045) with its shaft up +z and the port 60 % of the way to its
  // top vertex; it pivots there. The tip's distance from the port grows by the 4 mm insertion,
  // and it swings by about (depth0 + 4 mm) · angle.
  const auto at = [&](const char* key) {
    return std::array<double, 3>{d[key][0].get<double>(), d[key][1].get<double>(), d[key][2].get<double>()};
  };
  const auto s = at("start"), e = at("end");
  EXPECT_NEAR(s[2], 0.045, 1e-9);
  EXPECT_GT(d["travel_m"].get<double>(), 0.02);
  // Where the port kinematics put the pose for that command: the simulated instrument got there.
  trocar::Scene scene = trocar::load_scene(kScenes + "/probe_press_slide.json");
  trocar::DeviceSpec spec;
  spec.driver = "mouse";
  const trocar::PortKinematics k = trocar::port_kinematics(spec, scene.world.instruments[0]);
  trocar::PortCommand c;
  c.yaw = -0.4, c.pitch = 0.2, c.depth = 0.004;
  const trocar::Vec3 expected = k.pose(c).translation;
  const trocar::Vec3 end(e[0], e[1], e[2]);
  EXPECT_NEAR((end - expected).norm(), 0, 1e-3) << end.transpose() << " vs " << expected.transpose();
  // Pivoting keeps the tip at the start depth plus the insertion from the port.
  EXPECT_NEAR((end - k.pivot()).norm(), k.start_depth() + 0.004, 1e-3);
}

TEST(ViewCli, RealXMouseEventsThroughGlfwDriveTheInstrument) {
  Xvfb x;
  if (!x.running()) GTEST_SKIP() << "Xvfb cannot start here";
  if (run_program("command -v", "xdotool").exit_code != 0) GTEST_SKIP() << "xdotool is not installed";
  const fs::path report = temp("xdotool.json");
  // The X server delivers the events to GLFW, whose callbacks feed the same mapping: a left drag
  // from (640, 360) to (700, 390) gives yaw −60 · 0.004 and pitch 30 · 0.004 rad. Nothing is
  // timed: X keeps the events in order, xdotool --sync waits for each move, and Escape (after the
  // drag in the same stream) closes the window. Without the panel no press can be the panel's.
  // The script's exit status is the viewer's; --quit-after only bounds a lost Escape.
  const std::string script =
      "export DISPLAY=" + x.display() + "; " TROCAR_CLI " view " + kScenes +
      "/probe_press_slide.json --no-panel --quit-after 120 --report " + report.string() +
      " & v=$!; w=$(xdotool search --sync --onlyvisible --name trocar | head -1); xdotool windowmove --sync $w 0 0;"
      " xdotool mousemove --sync 640 360; xdotool mousedown 1;"
      " xdotool mousemove --sync 670 375; xdotool mousemove --sync 700 390; xdotool mouseup 1;"
      " xdotool key Escape; wait $v";
  const auto r = run_program("sh -c", "'" + script + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = read_json(report);
  EXPECT_LT(j["wall_time_s"].get<double>(), 120) << "Escape closed the window";
  EXPECT_NEAR(j["driven_instrument"]["command"]["yaw"].get<double>(), -0.24, 1e-9) << j.dump(2);
  EXPECT_NEAR(j["driven_instrument"]["command"]["pitch"].get<double>(), 0.12, 1e-9);
}

TEST(ViewCli, PauseStepResetAndARecordingThatReplays) {
  Xvfb x;
  if (!x.running()) GTEST_SKIP() << "Xvfb cannot start here";
  const fs::path events = temp("keys.txt"), report = temp("keys.json"), out = temp("recordings");
  fs::remove_all(out);
  {
    std::ofstream e(events);
    e << "f2 key pause\nf3 keyup pause\nf4 key step\nf5 keyup step\nf6 key pause\nf7 keyup pause\n"
         "f8 key reset\nf9 keyup reset\n"
         "f10 key record\nf11 keyup record\n"  // restarts the scene with a recording
         "f12 down 0 600 300\nf13 move 640 330\nf14 up 0 640 330\nf15 settle\nf16 key jaw\nf17 settle\nf18 keyup jaw\n"
         "f19 key record\nf20 keyup record\n";  // stops it; the scene goes on
  }
  const auto r = run_program("DISPLAY=" + x.display() + " " TROCAR_CLI,
                             "view " + kScenes + "/grasp_lift.json --no-panel --quit-after-frames 22 --inject " +
                                 events.string() + " --record-dir " + out.string() + " --report " + report.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = read_json(report);
  EXPECT_EQ(j["events_played"].get<int>(), 19);
  EXPECT_EQ(j["driven_instrument"]["command"]["jaw"].get<double>(), 0);  // released
  const fs::path rec = j["last_recording"].get<std::string>();
  ASSERT_TRUE(fs::exists(rec)) << rec;
  EXPECT_EQ(rec.parent_path(), out);
  // The recorded session (a mouse drag and a jaw closing) replays to the same state, bit for bit.
  const auto replay = run_program(TROCAR_CLI, "replay " + rec.string());
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_NE(replay.output.find("identical"), std::string::npos) << replay.output;
  // The recording holds the settled drag and jaw: at least the 2 × 200 steps waited for.
  const auto steps = replay.output.find("replay: ");
  ASSERT_NE(steps, std::string::npos) << replay.output;
  EXPECT_GE(std::stoul(replay.output.substr(steps + 8)), 400u) << replay.output;
}

TEST(ViewCli, SaysSoWithoutADisplay) {
  const auto r = run_program("env -u DISPLAY -u WAYLAND_DISPLAY " TROCAR_CLI, "view " + kScenes + "/hernia.json --quit-after 1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
}

TEST(RunFramesCli, RendersFramesHeadlessAndNamesAMissingFfmpeg) {
  const fs::path dir = temp("frames");
  fs::remove_all(dir);
  const auto r = run_program("env -u DISPLAY " TROCAR_CLI, "run " + kScenes + "/probe_press_slide.json --duration 0.2 --fps 20 "
                             "--size 161x121 --frames " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "frame_0004.png"));
  EXPECT_FALSE(fs::exists(dir / "frame_0005.png"));  // t = 0 … 0.2 s at 20 fps: 5 frames
  EXPECT_EQ(png_size(dir / "frame_0000.png"), std::make_pair(161, 121));
  // Without ffmpeg on PATH: a clear error naming it.
  const auto none = run_program("env -u DISPLAY PATH=/nonexistent " TROCAR_CLI, "run " + kScenes +
                                "/probe_press_slide.json --duration 0.05 --size 64x48 --video " + temp("x.mp4").string());
  EXPECT_EQ(none.exit_code, 1) << none.output;
  EXPECT_NE(none.output.find("ffmpeg is not installed"), std::string::npos) << none.output;
}

TEST(RunFramesCli, EncodesAVideoWithFfmpeg) {
  if (run_program("command -v", "ffmpeg").exit_code != 0) GTEST_SKIP() << "ffmpeg is not installed";
  const fs::path video = temp("run.mp4");
  fs::remove(video);
  const auto r = run_program("env -u DISPLAY " TROCAR_CLI, "run " + kScenes + "/probe_press_slide.json --duration 0.2 --fps 20 "
                             "--size 161x121 --video " + video.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(video), 1000u);
}

TEST(RunFramesCli, RejectsBadFrameOptions) {
  const std::string scene = kScenes + "/probe_press_slide.json --duration 0.01 ";
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {"--frames " + temp("f1").string() + " --camera nope", "no camera \"nope\""},
           {"--frames " + temp("f2").string() + " --size 12x", "--size"},
           {"--camera orbit", "go with --frames"}}) {
    const auto r = run_program(TROCAR_CLI, "run " + scene + args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << args << "\n" << r.output;
  }
}

}  // namespace
