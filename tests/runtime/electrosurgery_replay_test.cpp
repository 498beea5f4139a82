// A real-time session in which the hook cuts a sheet replays bit for bit (docs/electrosurgery.md,
// "Robustness"): the pedal is a device button held down, recorded as its press and release, and
// the cuts the replay makes are the session's. Time is a manual clock: the test counts periods.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "support/manual_clock.h"
#include "trocar/device/scripted_device.h"
#include "trocar/procedure/actions.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScene = R"({
  "schema": 1, "name": "hook-sheet", "timestep": 0.001, "duration": 1, "gravity": [0, 0, -9.81],
  "tissues": [{ "name": "peritoneum", "mesh": {"generate": "sheet", "width": 0.04, "height": 0.04, "nx": 20, "ny": 20},
                "material": {"preset": "peritoneum"},
                "fixed": {"inside_box": {"min": [-1, -1, -1], "max": [1, -0.0199, 1]}},
                "integrator": "xpbd" }],
  "instruments": [{ "name": "hook", "mesh": {"generate": "hook-probe"}, "shaft_direction": [0, 0, 1],
                    "electrode": {"power": 40},
                    "motion": {"keyframes": [{"t": 0, "position": [0, -0.01, -0.0002], "rotate_deg": [0, 0, 90]}]}}],
  "events": [{"t": 0.05, "action": "energy_on", "instrument": "hook"},
             {"t": 0.75, "action": "energy_off", "instrument": "hook"}]
})";

TEST(ElectrosurgeryReplay, ASessionThatCutsReplaysBitForBit) {
  const fs::path dir = fs::temp_directory_path() / ("trocar_burn_replay_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path scene_file = dir / "hook.json", recording = dir / "hook.trec";
  std::ofstream(scene_file) << kScene;
  Scene scene = load_scene(scene_file);
  ASSERT_EQ(scene.world.instruments[0].electrode.power, 40.0);
  // The scene's events became the scripted device's pedal: held from 0.05 s to 0.75 s.
  ASSERT_EQ(scene.devices[0].presses.size(), 1u);
  EXPECT_EQ(scene.devices[0].presses[0].buttons, kActionEnergyOn << 1);
  EXPECT_DOUBLE_EQ(scene.devices[0].presses[0].until, 0.75);
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> devices = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  RuntimeSettings settings;
  settings.lockstep = true;
  settings.duration = 0;
  settings.realtime_scheduling = false;
  test::ManualClock clock;
  settings.clock = &clock;
  RecordingWriter writer(recording, session_header(scene_file, read_scene_text(scene_file), sim, settings));
  std::vector<RuntimeChannel> channels = make_channels(devices, sim.world());
  Runtime runtime(sim, std::move(channels), settings, &writer);
  const RuntimeReport report = test::run_for_periods(runtime, clock, 1, 900, 1000000);
  finish_recording(writer, sim);
  EXPECT_EQ(report.recording_dropped, 0u);
  // It cut (a session without a cut would prove little), and let go of the pedal.
  const BurnTally burnt = sim.burn_tally(0);
  EXPECT_GT(burnt.cut_triangles, 0u);
  EXPECT_FALSE(sim.energy_on(0));
  const Recording rec = read_recording(recording, true);
  int on = 0, off = 0;
  for (const StepRecord& s : rec.steps) {
    on += (s.instrument[0].actions & kActionEnergyOn) ? 1 : 0;
    off += (s.instrument[0].actions & kActionEnergyOff) ? 1 : 0;
  }
  EXPECT_EQ(on, 1);
  EXPECT_EQ(off, 1);
  const ReplayResult r = replay_recording(recording);
  EXPECT_EQ(r.steps, report.physics_steps);
  EXPECT_TRUE(r.matches()) << hash_hex(r.state_hash) << " vs " << hash_hex(r.recorded_hash);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace trocar
