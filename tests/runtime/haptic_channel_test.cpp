// The haptic path of one instrument with a scripted stand-in device: a dropped device zeroes the
// force within one tick and the instrument holds its pose; reconnecting goes through the safe
// start; a stale model fades; a new model's jump is spread over the blend.
#include <gtest/gtest.h>

#include "trocar/runtime/haptic_channel.h"

namespace trocar {
namespace {

class FakeDevice final : public Device {
 public:
  FakeDevice() { specs_.max_force = 3.3; specs_.damping = 2; }
  void open() override {}
  void close() override {}
  DeviceStatus read(double, DeviceInput& in) override {
    if (status == DeviceStatus::kConnected) {
      sample.sequence += 1;
      in = sample;
    }
    return status;
  }
  void write(const DeviceOutput& o) override { last = o; }
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override { return {}; }

  DeviceStatus status = DeviceStatus::kConnected;
  DeviceInput sample;
  DeviceOutput last;

 private:
  DeviceSpecs specs_;
};

LocalContactModel contact(double force_z) {
  LocalContactModel m;
  m.position0 = Vec3(0, 0, 0);
  m.force0 = Vec3(0, 0, force_z);
  m.normal = Vec3(0, 0, 1);
  m.stiffness = 1000;
  m.in_contact = true;
  return m;
}

struct Rig {
  FakeDevice device;
  ForceShaping shaping;
  ModelHandover handover;
  std::unique_ptr<HapticChannel> channel;
  TickInstrument record;
  std::uint64_t step = 0;
  double t = 0;
  Rig(int blend_ticks = 1) {
    shaping.ramp_time = 0;  // on at once once engaged (the ramp has its own test)
    shaping.slew_rate = 1e6;
    handover.blend_ticks = blend_ticks;
    channel = std::make_unique<HapticChannel>(device, DeviceMapping{}, CouplingSettings{1000, 0}, shaping, handover);
  }
  Vec3 tick(const LocalContactModel& m, bool new_model, double age = 0) {
    if (new_model) ++step;
    channel->sense(t);
    channel->actuate(m, step, age, 1e-3, record);
    t += 1e-3;
    return channel->force();
  }
};

TEST(HapticChannel, DropZeroesForceInOneTickHoldsPoseAndReconnectsSafely) {
  Rig rig;
  rig.device.sample.pose.translation = Vec3(0, 0, 0.0);
  EXPECT_NEAR(rig.tick(contact(0.1), true).z(), 0.1, 1e-12);  // small: engages at once
  EXPECT_NEAR(rig.tick(contact(1.0), true).z(), 1.0, 1e-12);
  EXPECT_EQ(Vec3(rig.device.last.force), Vec3(0, 0, 1.0));     // written to the device
  const Pose held = rig.channel->command().pose;

  rig.device.status = DeviceStatus::kDisconnected;
  rig.device.sample.pose.translation = Vec3(0.05, 0, 0);  // (not delivered)
  EXPECT_EQ(rig.tick(contact(1.0), true), Vec3::Zero());   // the very next tick
  EXPECT_EQ(Vec3(rig.device.last.force), Vec3::Zero());
  EXPECT_EQ(rig.channel->command().pose.translation, held.translation);
  EXPECT_EQ(rig.channel->disconnects(), 1u);
  EXPECT_EQ(rig.record.status, static_cast<std::uint32_t>(DeviceStatus::kDisconnected));

  // Back while pressing 1 N: the safe start keeps the force off until it is below 0.2 N.
  rig.device.status = DeviceStatus::kConnected;
  rig.device.sample.pose.translation = Vec3(0, 0, 0);
  EXPECT_EQ(rig.tick(contact(1.0), true), Vec3::Zero());
  EXPECT_EQ(rig.record.engaged, 0u);
  EXPECT_NEAR(rig.tick(contact(0.15), true).z(), 0.15, 1e-12);
  EXPECT_EQ(rig.record.engaged, 1u);
  EXPECT_NEAR(rig.tick(contact(1.0), true).z(), 1.0, 1e-12);
}

TEST(HapticChannel, StaleModelFadesToZero) {
  Rig rig;
  rig.tick(contact(0.1), true);
  const LocalContactModel m = contact(0.1);
  EXPECT_NEAR(rig.tick(m, false, 0.009).z(), 0.1, 1e-12);     // younger than 10 ms: full
  EXPECT_NEAR(rig.tick(m, false, 0.0125).z(), 0.05, 1e-12);   // half way through the 5 ms fade
  EXPECT_EQ(rig.tick(m, false, 0.016), Vec3::Zero());         // past it
}

TEST(HapticChannel, NewModelJumpIsSpreadOverTheBlend) {
  Rig rig(4);
  rig.tick(contact(0.1), true);
  for (int i = 0; i < 4; ++i) rig.tick(contact(0.1), false);  // settled at 0.1 N
  // A model 1 N higher arrives: 0.1 + 0.9·(1/4, 2/4, 3/4, 1).
  const double expect[] = {0.325, 0.55, 0.775, 1.0};
  EXPECT_NEAR(rig.tick(contact(1.0), true).z(), expect[0], 1e-12);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(rig.tick(contact(1.0), false).z(), expect[i], 1e-12);
  EXPECT_NEAR(rig.tick(contact(1.0), false).z(), 1.0, 1e-12);
}

TEST(HapticChannel, ForceFollowsTheDeviceBetweenModels) {
  Rig rig;
  rig.tick(contact(0.1), true);
  rig.tick(contact(1.0), true);
  // 2 mm deeper without a new model: k_s = 1000·1000/2000 = 500 N/m → +1 N.
  rig.device.sample.pose.translation = Vec3(0, 0, -0.002);
  EXPECT_NEAR(rig.tick(contact(1.0), false).z(), 2.0, 1e-12);
  // The instrument goes where the device is (physics follows the device).
  EXPECT_NEAR(rig.channel->command().pose.translation.z(), -0.002, 1e-15);
}

}  // namespace
}  // namespace trocar
