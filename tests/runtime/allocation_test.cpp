// The haptic tick and the runtime's physics step allocate nothing after warm-up
// (docs/architecture.md "Conventions"): a scripted device presses the shipped press scene's lobe in
// 0.5 s and holds, in lock-step (the tick then holds the physics step too) with a recorder
// attached; counted over the held second.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/allocation_counter.h"
#include "trocar/device/scripted_device.h"
#include "trocar/runtime/haptic_channel.h"
#include "trocar/runtime/physics_stepper.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

TEST(RuntimeAllocation, HapticTickAndPhysicsStepAllocateNothingAfterWarmUp) {
  ASSERT_EQ(test::probe_counted_allocations(), 2) << "the counting operator new is not linked";
  Scene scene = load_scene(std::filesystem::path(TROCAR_TEST_SCENES) / "probe_press_slide.json");
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> devices = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  std::vector<RuntimeChannel> channels = make_channels(devices, sim.world());
  Keyframe top, pressed;
  top.position = Vec3(0, 0, 0.045);
  pressed.t = 0.5;
  pressed.position = Vec3(0, 0, 0.0225);
  ScriptedDevice device(KeyframeMotion({top, pressed}));
  HapticChannel channel(device, channels[0].mapping, channels[0].coupling, channels[0].shaping, {});
  PhysicsStepper stepper(sim, 500);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("trocar_alloc_" + std::to_string(::getpid()) + ".trec");
  RecordingHeader header;
  header.instruments = 1;
  RecordingWriter writer(file, header);
  InstrumentCommandSet commands;
  StepRecord step_record;
  TickRecord tick_record;
  tick_record.instruments = 1;
  double peak = 0;
  long counted = 0;
  for (int k = 0; k < 2000; ++k) {
    // Warm-up: the press and 0.5 s of hold (the detector and the response size their buffers
    // on their first contacts).
    if (k == 1000) {
      test::g_allocations = 0;
      test::g_counting = true;
    }
    const double t = k * 1e-3;
    commands.instruments[0] = channel.sense(t);
    const ContactModelSet& m = stepper.step(commands, 1e-3, 0, step_record);
    channel.actuate(m.instruments[0], m.step, 0, 1e-3, tick_record.instrument[0]);
    writer.push_step(step_record);
    writer.push_tick(tick_record);
    peak = std::max(peak, channel.force().norm());
  }
  test::g_counting = false;
  counted = test::g_allocations;
  EXPECT_EQ(counted, 0);
  EXPECT_GT(peak, 0.1);  // it was really pressing
  writer.finish(EndRecord{});
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace trocar
