// Two instruments at once (the seed's two PHANTOMs): each has its own device and channel; both
// press the same ball from opposite sides, each feels its own force, and the session replays.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/manual_clock.h"
#include "trocar/device/scripted_device.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

const char* kTwoProbes = R"({"schema": 1, "name": "two-probes", "timestep": 0.001, "gravity": [0, 0, 0],
 "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3},
   "material": {"preset": "liver"}, "fixed": {"below_plane": {"point": [0, 0, -0.02], "normal": [0, 0, 1]}}}],
 "instruments": [
   {"name": "left", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},
    "motion": {"keyframes": [{"t": 0, "position": [-0.034, 0, 0], "rotate_deg": [0, -90, 0]},
                             {"t": 0.2, "position": [-0.024, 0, 0], "rotate_deg": [0, -90, 0]}]}},
   {"name": "right", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},
    "motion": {"keyframes": [{"t": 0, "position": [0.034, 0, 0], "rotate_deg": [0, 90, 0]},
                             {"t": 0.2, "position": [0.024, 0, 0], "rotate_deg": [0, 90, 0]}]}}]})";

TEST(Bimanual, TwoDevicesEachFeelTheirOwnSide) {
  Scene scene = parse_scene(kTwoProbes, "two-probes.json", ".");
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> devices = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("trocar_bimanual_" + std::to_string(::getpid()) + ".trec");
  RuntimeSettings settings;
  settings.lockstep = true;
  settings.duration = 0;  // until stopped, after 500 periods of the manual clock
  settings.realtime_scheduling = false;
  test::ManualClock clock;
  settings.clock = &clock;
  RecordingWriter writer(file, session_header("two-probes.json", kTwoProbes, sim, settings));
  Runtime runtime(sim, make_channels(devices, sim.world()), settings, &writer);
  const RuntimeReport report = test::run_for_periods(runtime, clock, 1, 500, 1000000);
  EXPECT_EQ(report.ticks, 501u);  // 500 periods and the stopping one
  finish_recording(writer, sim);
  ASSERT_EQ(report.devices.size(), 2u);
  const Recording rec = read_recording(file, true);
  double left_x = 0, right_x = 0;  // the most negative / positive force along x each felt (N)
  for (const TickRecord& t : rec.ticks) {
    ASSERT_EQ(t.instruments, 2u);
    left_x = std::min(left_x, t.instrument[0].force[0]);
    right_x = std::max(right_x, t.instrument[1].force[0]);
  }
  // The ball pushes the left probe back to −x and the right one to +x.
  EXPECT_LT(left_x, -0.05);
  EXPECT_GT(right_x, 0.05);
  EXPECT_TRUE(replay_recording(file).matches());
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace trocar
