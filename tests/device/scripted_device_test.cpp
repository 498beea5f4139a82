// The scripted driver: a scene's keyframes at the read time, and its scripted button presses held
// for ScriptedDevice::kPressTime from each press's time (docs/devices.md).
#include <gtest/gtest.h>

#include "trocar/device/scripted_device.h"

namespace trocar {
namespace {

KeyframeMotion line() {
  Keyframe a, b;
  a.t = 0;
  b.t = 1;
  b.position = Vec3(0.1, 0, 0);
  return KeyframeMotion({a, b});
}

TEST(ScriptedDevice, PlaysTheKeyframesAndHoldsEachPressForItsTime) {
  ScriptedDevice device(line(), 3.3, 2.0, {{0.2, 1u << 1}, {0.5, 1u << 2}});
  DeviceInput in;
  ASSERT_EQ(device.read(0.22, in), DeviceStatus::kConnected);
  EXPECT_NEAR(in.pose.translation.x(), 0.022, 1e-12);
  EXPECT_NEAR(in.velocity.x(), 0.1, 1e-9);  // 0.1 m in 1 s
  EXPECT_EQ(in.buttons, 1u << 1);           // within the fire press, held [0.2, 0.25)
  const struct {
    double t;
    std::uint32_t buttons;
  } cases[] = {{0.0, 0}, {0.199, 0}, {0.2, 1u << 1}, {0.2499, 1u << 1}, {0.2501, 0}, {0.5, 1u << 2}, {0.549, 1u << 2},
               {0.551, 0}, {2.0, 0}};
  for (const auto& c : cases) {
    device.read(c.t, in);
    EXPECT_EQ(in.buttons, c.buttons) << "at " << c.t << " s";
  }
  ScriptedDevice silent(line());
  silent.read(0.2, in);
  EXPECT_EQ(in.buttons, 0u);
}

}  // namespace
}  // namespace trocar
