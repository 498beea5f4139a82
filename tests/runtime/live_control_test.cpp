// The runtime as the viewer drives it: run until stopped, pause and single steps, view snapshots
// through the triple buffer, live counters, and the mouse driver moving an instrument. Time is a
// manual clock: the test moves it one haptic period at a time and counts what the loops did.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "support/manual_clock.h"
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

constexpr std::int64_t kPeriod = 1000000;  // ns: 1 kHz, and the scene's 1 ms step

/// A runtime on the ball scene with a manual clock, running on its own thread until stopped.
struct ClockedRun {
  Simulation sim;
  PortDevice* port = nullptr;
  test::ManualClock clock;
  std::unique_ptr<Runtime> runtime;
  RuntimeReport report;
  std::thread thread;
  int loops = 2;  // the haptic and the physics thread (lock-step: the haptic one only)

  ClockedRun(Scene scene, bool lockstep, double duration = 0)
      : sim(std::move(scene.world), [&] {
          scene.settings.measure_penetration = false;
          return scene.settings;
        }()) {
    std::vector<RuntimeChannel> channels = make_channels(scene.devices, sim.world());
    port = dynamic_cast<PortDevice*>(channels[0].device.get());
    RuntimeSettings settings;
    settings.duration = duration;  // 0: until request_stop
    settings.realtime_scheduling = false;
    settings.lockstep = lockstep;
    settings.view_rate_hz = lockstep ? 0 : 100;
    settings.clock = &clock;
    loops = lockstep ? 1 : 2;
    runtime = std::make_unique<Runtime>(sim, std::move(channels), settings);
    thread = std::thread([this] { report = runtime->run(); });
  }
  ~ClockedRun() { test::stop_and_join(*runtime, clock, thread, kPeriod); }
  /// Waits for the loops to park on the start, then moves the clock there: the first tick and step.
  void start() {
    ASSERT_TRUE(clock.settle(loops)) << "the runtime's loops did not reach their start";
    clock.advance(clock.next_deadline() - clock.now_ns());
    ASSERT_TRUE(clock.settle(loops)) << "the first tick did not finish";
  }
  /// Moves the clock `n` periods, one at a time, each time until the loops are parked again.
  void periods(int n) {
    for (int i = 0; i < n; ++i) {
      clock.advance(kPeriod);
      ASSERT_TRUE(clock.settle(loops)) << "a loop did not finish period " << i;
    }
  }
  std::uint64_t ticks() const { return runtime->live().ticks.load(); }
  std::uint64_t steps() const { return runtime->live().physics_steps.load(); }
  /// Lock-step steps inside the tick: read while the loop is parked.
  std::uint64_t sim_steps() const { return sim.metrics().step_index; }
  /// Stops the run (see stop_and_join); returns the haptic loop's ticks after the request.
  std::uint64_t stop() {
    const std::uint64_t before = ticks();
    EXPECT_TRUE(test::stop_and_join(*runtime, clock, thread, kPeriod)) << "run() did not end within 30 s of request_stop";
    return report.ticks - before;
  }
};

Scene ball_scene() { return parse_scene(kBall, "ball.json", "."); }

TEST(LiveControl, PausesStepsPublishesViewsAndStopsOnRequest) {
  ClockedRun run(ball_scene(), /*lockstep=*/false);
  ASSERT_NE(run.port, nullptr);
  EXPECT_NEAR((run.port->kinematics().pivot() - Vec3(0, 0, 0.1)).norm(), 0, 1e-12);
  Runtime& runtime = *run.runtime;
  run.start();
  EXPECT_EQ(run.ticks(), 1u);
  EXPECT_EQ(run.steps(), 1u);

  // Views arrive every 10 periods (100 Hz), each with the step it was taken after.
  ASSERT_TRUE(runtime.views().update());
  EXPECT_EQ(runtime.views().front().step, 1u);
  EXPECT_EQ(runtime.views().front().tissues.size(), 1u);
  run.periods(9);
  EXPECT_FALSE(runtime.views().update()) << "no view before 10 ms";
  run.periods(1);
  ASSERT_TRUE(runtime.views().update());
  EXPECT_EQ(runtime.views().front().step, 11u);
  EXPECT_EQ(run.ticks(), 11u);
  EXPECT_EQ(run.steps(), 11u);

  // The mouse pushes the probe 1 cm deeper; 100 ms later the view shows it there.
  PortCommand c;
  c.depth = 0.01;
  run.port->set(c);
  run.periods(100);
  ASSERT_TRUE(runtime.views().update());
  EXPECT_EQ(runtime.views().front().step, 111u);
  EXPECT_NEAR(runtime.views().front().instruments[0].pose.translation.z(), 0.024, 1e-3);

  // Paused: no steps while the haptic loop ticks on; step_once: exactly one.
  runtime.set_paused(true);
  const std::uint64_t held = run.steps(), ticks = run.ticks();
  run.periods(50);
  EXPECT_EQ(run.steps(), held);
  EXPECT_EQ(run.ticks(), ticks + 50) << "the haptic loop runs on while paused";
  runtime.step_once();
  run.periods(1);
  EXPECT_EQ(run.steps(), held + 1);
  run.periods(20);
  EXPECT_EQ(run.steps(), held + 1);
  runtime.set_paused(false);
  run.periods(30);
  EXPECT_EQ(run.steps(), held + 31);
  EXPECT_EQ(run.ticks(), ticks + 101);
  EXPECT_EQ(runtime.live().late_ticks.load(), 0u);

  // request_stop ends the haptic loop after one more tick.
  EXPECT_EQ(run.stop(), 1u);
  EXPECT_FALSE(runtime.live().running.load());
  EXPECT_EQ(run.report.ticks, 213u);
  EXPECT_EQ(run.report.physics_steps, run.sim.metrics().step_index);
}

TEST(LiveControl, AStallSkipsTheMissedSlotsAndCountsThem) {
  ClockedRun run(ball_scene(), /*lockstep=*/true);
  run.start();
  run.periods(99);
  EXPECT_EQ(run.ticks(), 100u);
  EXPECT_EQ(run.sim_steps(), 100u);  // lock-step: one step in each tick
  EXPECT_EQ(run.runtime->live().late_ticks.load(), 0u);
  // The loop is held up (as by a page fault) until 8 periods after the slot it waits for: that
  // slot runs late, the next 6 are skipped, the 7th runs 1 period late and the 8th on time. Back
  // on its grid after 3 ticks instead of a burst of 9.
  run.clock.advance(9 * kPeriod);
  ASSERT_TRUE(run.clock.settle(1));
  EXPECT_EQ(run.ticks(), 103u);
  EXPECT_EQ(run.sim_steps(), 103u);
  EXPECT_EQ(run.runtime->live().late_ticks.load(), 2u + 6u);  // late ticks plus skipped slots
  run.periods(10);
  EXPECT_EQ(run.ticks(), 113u);
  EXPECT_EQ(run.stop(), 1u);
  // Every slot of the run was either ticked (114) or counted as missed (6 skipped, 2 late).
  EXPECT_EQ(run.report.ticks, 114u);
  EXPECT_DOUBLE_EQ(run.report.deadline_miss_fraction, 8.0 / 120.0);
  EXPECT_EQ(run.report.physics_steps, 114u);
}

TEST(LiveControl, AStallOverTheLastSlotStillCountsEverySlotOfTheRun) {
  // 10 periods. The loop waits for slot 8 and is held up until 2.5 periods past it: slot 8 runs
  // late, slot 9 (the run's last) is skipped, and the run ends: 9 ticks + 1 skipped = 10 slots.
  ClockedRun run(ball_scene(), /*lockstep=*/true, /*duration=*/0.010);
  run.start();
  run.periods(7);
  EXPECT_EQ(run.ticks(), 8u);
  run.clock.advance(3 * kPeriod + kPeriod / 2);
  EXPECT_TRUE(test::stop_and_join(*run.runtime, run.clock, run.thread, kPeriod));
  EXPECT_EQ(run.report.ticks, 9u);
  EXPECT_EQ(run.report.skipped_slots, 1u);
  EXPECT_EQ(run.report.ticks + run.report.skipped_slots, 10u);
  EXPECT_DOUBLE_EQ(run.report.deadline_miss_fraction, 2.0 / 10.0);  // one late, one skipped
}

}  // namespace
}  // namespace trocar
