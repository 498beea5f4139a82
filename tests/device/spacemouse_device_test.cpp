// The spacemouse driver's rate control (deflection → velocity → pose) and its error without the
// spacenavd daemon.
#include <gtest/gtest.h>

#ifdef TROCAR_HAVE_SPNAV
#include <cmath>

#include "trocar/core/error.h"
#include "trocar/device/spacemouse_device.h"

namespace trocar {
namespace {

TEST(SpaceMouseIntegrator, FullDeflectionMovesAtTheConfiguredSpeed) {
  SpaceMouseSettings s;  // 0.05 m/s, 1 rad/s at 350 units, dead zone 5 %
  SpaceMouseIntegrator i(s);
  SpaceMouseDeflection d;
  d.t[0] = 350;
  for (int k = 0; k < 1000; ++k) i.advance(d, 1e-3);
  EXPECT_NEAR((i.pose().translation - Vec3(0.05, 0, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR(i.velocity().x(), 0.05, 1e-12);
  d.t[0] = 700;  // past full: clamped
  i.advance(d, 0.1);
  EXPECT_NEAR(i.pose().translation.x(), 0.055, 1e-9);
}

TEST(SpaceMouseIntegrator, DeadZoneIgnoresSmallDeflection) {
  SpaceMouseIntegrator i;
  SpaceMouseDeflection d;
  d.t[1] = 0.04 * 350;
  d.r[2] = -0.04 * 350;
  for (int k = 0; k < 1000; ++k) i.advance(d, 1e-3);
  EXPECT_EQ(i.pose().translation, Vec3::Zero());
  EXPECT_NEAR(i.pose().rotation.angularDistance(Quat::Identity()), 0, 1e-15);
}

TEST(SpaceMouseIntegrator, RotationIntegratesTheAngle) {
  SpaceMouseIntegrator i;
  SpaceMouseDeflection d;
  d.r[2] = 350;
  for (int k = 0; k < 500; ++k) i.advance(d, 1e-3);
  EXPECT_NEAR(i.pose().rotation.angularDistance(Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ()))), 0, 1e-9);
}

TEST(SpaceMouseDevice, NoDaemonIsAClearError) {
  SpaceMouseDevice device{SpaceMouseSettings{}};
  try {
    device.open();
    device.close();
    GTEST_SKIP() << "a spacenavd daemon is running here";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("spacenavd"), std::string::npos) << e.what();
  }
  DeviceInput in;
  EXPECT_EQ(device.read(0, in), DeviceStatus::kDisconnected);
}

}  // namespace
}  // namespace trocar
#else
TEST(SpaceMouse, NotBuilt) { GTEST_SKIP() << "libspnav-dev was not found at configure time"; }
#endif
