// The runtime as the viewer drives it: run until stopped, pause and single steps, view snapshots
// through the triple buffer, live counters, and the mouse driver moving an instrument.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "trocar/device/port_device.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

const char* kBall = R"({"schema": 1, "name": "ball", "timestep": 0.001, "gravity": [0, 0, 0],
 "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 2},
   "material": {"preset": "liver"}, "fixed": {"below_plane": {"point": [0, 0, -0.02], "normal": [0, 0, 1]}}}],
 "instruments": [{"name": "probe", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},
   "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.034]}]},
   "device": {"driver": "mouse", "pivot": [0, 0, 0.1]}}]})";

using namespace std::chrono_literals;

TEST(LiveControl, PausesStepsPublishesViewsAndStopsOnRequest) {
  Scene scene = parse_scene(kBall, "ball.json", ".");
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> devices = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  std::vector<RuntimeChannel> channels = make_channels(devices, sim.world());
  auto* port = dynamic_cast<PortDevice*>(channels[0].device.get());
  ASSERT_NE(port, nullptr);
  EXPECT_NEAR((port->kinematics().pivot() - Vec3(0, 0, 0.1)).norm(), 0, 1e-12);
  RuntimeSettings settings;
  settings.duration = 0;  // until request_stop
  settings.realtime_scheduling = false;
  settings.view_rate_hz = 100;
  Runtime runtime(sim, std::move(channels), settings);
  RuntimeReport report;
  std::thread t([&] { report = runtime.run(); });
  while (!runtime.live().running.load()) std::this_thread::sleep_for(1ms);

  // Views arrive with increasing steps.
  std::this_thread::sleep_for(100ms);
  ASSERT_TRUE(runtime.views().update());
  const std::uint64_t first = runtime.views().front().step;
  EXPECT_GT(first, 0u);
  EXPECT_EQ(runtime.views().front().tissues.size(), 1u);
  std::this_thread::sleep_for(60ms);
  runtime.views().update();
  EXPECT_GT(runtime.views().front().step, first);

  // The mouse pushes the probe 1 cm deeper; the view shows it there.
  PortCommand c;
  c.depth = 0.01;
  port->set(c);
  std::this_thread::sleep_for(100ms);
  runtime.views().update();
  EXPECT_NEAR(runtime.views().front().instruments[0].pose.translation.z(), 0.024, 1e-3);

  // Paused: no steps; step_once: exactly one.
  runtime.set_paused(true);
  std::this_thread::sleep_for(20ms);
  const std::uint64_t held = runtime.live().physics_steps.load();
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(runtime.live().physics_steps.load(), held);
  runtime.step_once();
  std::this_thread::sleep_for(30ms);
  EXPECT_EQ(runtime.live().physics_steps.load(), held + 1);
  const std::uint64_t ticks = runtime.live().ticks.load();
  std::this_thread::sleep_for(20ms);
  EXPECT_GT(runtime.live().ticks.load(), ticks);  // the haptic loop runs on while paused
  runtime.set_paused(false);
  std::this_thread::sleep_for(30ms);
  EXPECT_GT(runtime.live().physics_steps.load(), held + 10);

  const auto t0 = std::chrono::steady_clock::now();
  runtime.request_stop();
  t.join();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 200ms);
  EXPECT_FALSE(runtime.live().running.load());
  EXPECT_GT(report.ticks, 300u);
  EXPECT_EQ(report.physics_steps, sim.metrics().step_index);
}

}  // namespace
}  // namespace trocar
