// The task on the real-time runtime (docs/procedure.md, "Actions and ports"): a device button
// fires the tacker once per press, the procedure is evaluated after every physics step, its panel
// is published with the views, and a recording of the session replays to the same tacks. Time is
// a manual clock (tests/support/manual_clock.h): the test counts periods, never waits on them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <unistd.h>

#include "procedure/task_scene.h"
#include "support/manual_clock.h"
#include "trocar/device/port_device.h"
#include "trocar/procedure/procedure.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

constexpr std::int64_t kPeriod = 1000000;  // ns: 1 kHz, the scene's 1 ms step

/// The procedure tests' wall, mesh and sac with a tacker whose tip rests 0.5 mm above the mesh
/// (both within the tacker's 2 mm). `device`: keys spliced after its mesh (its "device"), none:
/// the scripted driver; `extra`: root keys after the task (its "events").
std::string tacker_scene_text(const std::string& device, const std::string& extra = "") {
  std::string text = test::task_scene_text(R"("task": {"sac": "sac", "mesh": "mesh"})" + extra, "[0.01, 0.01, 0.0015]");
  const std::string capsule = R"({"generate": "capsule", "radius": 0.0025, "length": 0.05,
                                               "segments": 12, "rings": 3})";
  const auto at = text.find(capsule);
  EXPECT_NE(at, std::string::npos);
  text.replace(at, capsule.size(), R"({"generate": "tacker", "shaft_length": 0.05})" + device);
  return text;
}

/// Lets the runtime's loops reach their first deadline on the manual clock.
void start(test::ManualClock& clock) {
  ASSERT_TRUE(clock.settle(2));
  clock.advance(clock.next_deadline() - clock.now_ns());
  ASSERT_TRUE(clock.settle(2));
}

/// Advances the manual clock by n periods, each one settled.
void periods(test::ManualClock& clock, int n) {
  for (int i = 0; i < n; ++i) {
    clock.advance(kPeriod);
    ASSERT_TRUE(clock.settle(2)) << "a loop did not finish period " << i;
  }
}

TEST(ProcedureRuntime, ADeviceButtonFiresOncePerPressAndThePanelIsPublished) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("trocar_proc_rt_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path scene_file = dir / "tack.json", recording = dir / "tack.trec";
  const std::string text =
      tacker_scene_text(R"(, "device": {"driver": "mouse", "pivot": [0.01, 0.01, 0.1]})");  // the viewer's mouse driver
  {
    std::ofstream(scene_file) << text;
  }
  Scene scene = parse_scene(text, scene_file.string(), dir);
  scene.settings.measure_penetration = false;
  Simulation sim(std::move(scene.world), scene.settings);
  Procedure procedure(*scene.task, sim.world(), scene.zones, scene.landmarks);
  std::vector<RuntimeChannel> channels = make_channels(scene.devices, sim.world());
  PortDevice* port = dynamic_cast<PortDevice*>(channels[0].device.get());
  ASSERT_NE(port, nullptr);
  test::ManualClock clock;
  RuntimeSettings settings;
  settings.duration = 0;
  settings.realtime_scheduling = false;
  settings.view_rate_hz = 100;
  settings.clock = &clock;
  RecordingWriter recorder(recording, session_header(scene_file, text, sim, settings));
  Runtime runtime(sim, std::move(channels), settings, &recorder);
  runtime.set_procedure(&procedure);
  RuntimeReport report;
  std::thread thread([&] { report = runtime.run(); });
  start(clock);
  periods(clock, 5);
  EXPECT_EQ(procedure.tacks().size(), 0u);

  PortCommand press;
  press.buttons = 1u << 1;  // button 1: fire
  port->set(press);
  periods(clock, 20);  // held for 20 periods: one tack, on the press
  EXPECT_EQ(procedure.tacks().size(), 1u);
  port->set(PortCommand{});
  periods(clock, 3);
  port->set(press);
  periods(clock, 3);
  ASSERT_EQ(procedure.tacks().size(), 2u);
  EXPECT_EQ(procedure.tacks()[0].outcome, TackOutcome::kFixed);
  EXPECT_EQ(sim.attachments().size(), 2u);

  // The panel comes with the views: three steps, and the tacks among its events.
  periods(clock, 10);
  ASSERT_TRUE(runtime.task_views().update());
  const TaskView& panel = runtime.task_views().front();
  ASSERT_EQ(panel.steps.size(), 3u);
  EXPECT_EQ(panel.steps[0].name, "sac reduced");
  std::size_t tack_events = 0;
  for (const TaskEventView& e : panel.events) tack_events += e.text.find("tack") != std::string::npos ? 1 : 0;
  EXPECT_EQ(tack_events, 2u);

  EXPECT_TRUE(test::stop_and_join(runtime, clock, thread, kPeriod));
  finish_recording(recorder, sim);
  // The replay fires through the scene's task as the session did: the same tacks, the same state.
  const ReplayResult replay = replay_recording(recording);
  EXPECT_TRUE(replay.matches()) << replay.verdict();
  std::filesystem::remove_all(dir);
}

// A scene's scripted "events" play on the runtime too: the scripted device presses the fire button
// at each event's time (docs/procedure.md, "Actions and ports"), so `trocar view` of a track fires
// where `trocar run` does. Two fires 70 ms apart (each held 50 ms) give two tacks, none before the
// first.
TEST(ProcedureRuntime, TheScenesScriptedFireEventsArePressedByItsScriptedDevice) {
  const std::string text = tacker_scene_text("", R"(,
  "events": [{"t": 0.010, "action": "fire", "instrument": "tacker"}, {"t": 0.080, "action": "fire", "instrument": "tacker"}])");
  Scene scene = parse_scene(text, "events.json", ".");
  ASSERT_EQ(scene.devices.size(), 1u);
  ASSERT_EQ(scene.devices[0].presses.size(), 2u);
  EXPECT_EQ(scene.devices[0].presses[0].buttons, 1u << 1);  // button 1: fire
  scene.settings.measure_penetration = false;
  Simulation sim(std::move(scene.world), scene.settings);
  Procedure procedure(*scene.task, sim.world(), scene.zones, scene.landmarks);
  test::ManualClock clock;
  RuntimeSettings settings;
  settings.duration = 0;
  settings.realtime_scheduling = false;
  settings.clock = &clock;
  Runtime runtime(sim, make_channels(scene.devices, sim.world()), settings);
  runtime.set_procedure(&procedure);
  std::thread thread([&] { runtime.run(); });
  start(clock);
  periods(clock, 5);
  EXPECT_EQ(procedure.tacks().size(), 0u);  // before the first event
  periods(clock, 20);
  EXPECT_EQ(procedure.tacks().size(), 1u);  // the first press, held 50 ms, fires once
  periods(clock, 80);
  ASSERT_EQ(procedure.tacks().size(), 2u);
  EXPECT_EQ(procedure.tacks()[0].outcome, TackOutcome::kFixed);
  EXPECT_TRUE(test::stop_and_join(runtime, clock, thread, kPeriod));
}

}  // namespace
}  // namespace trocar
