// The mouse driver's port kinematics: a pivot about the trocar port plus a slide along the shaft.
#include <gtest/gtest.h>

#include <cmath>

#include "trocar/device/port_device.h"

namespace trocar {
namespace {

// A tool whose tip is at (0, 0, 0.05) with its shaft up +z; the port 0.06 m up the shaft.
const Pose kStart = Pose::from_euler_deg(Vec3(0, 0, 0.05), Vec3::Zero());
const Vec3 kPivot(0, 0, 0.11);

TEST(PortKinematics, PivotsAboutThePortAndSlidesAlongTheShaft) {
  const PortKinematics k(kStart, Vec3(0, 0, 1), kPivot);
  EXPECT_NEAR(k.start_depth(), 0.06, 1e-12);
  EXPECT_NEAR((k.pose({}).translation - kStart.translation).norm(), 0, 1e-12);
  for (double yaw : {-0.7, 0.0, 0.3})
    for (double pitch : {-0.4, 0.0, 0.5}) {
      PortCommand c;
      c.yaw = yaw, c.pitch = pitch, c.depth = 0.01;
      const Pose p = k.pose(c);
      // The tip is 0.06 + 0.01 m from the port, along the rotated shaft (the shaft still passes
      // through the port), and the rotation turns the shaft the same way.
      EXPECT_NEAR((p.translation - kPivot).norm(), 0.07, 1e-12);
      const Vec3 shaft = p.apply_vector(Vec3(0, 0, 1));
      EXPECT_NEAR(shaft.cross((kPivot - p.translation).normalized()).norm(), 0, 1e-12);
    }
  // Pitch 90° lays the shaft horizontal: tip 0.06 m from the port, level with it.
  PortCommand flat;
  flat.pitch = std::acos(0.0);
  EXPECT_NEAR(k.pose(flat).translation.z(), kPivot.z(), 1e-12);
}

TEST(PortKinematics, RollSpinsAboutTheShaftAndTheTipStaysInside) {
  const PortKinematics k(kStart, Vec3(0, 0, 1), kPivot);
  PortCommand roll;
  roll.roll = 1.0;
  const Pose p = k.pose(roll);
  EXPECT_NEAR((p.translation - kStart.translation).norm(), 0, 1e-12);  // the tip is on the axis
  EXPECT_NEAR(p.apply_vector(Vec3(1, 0, 0)).x(), std::cos(1.0), 1e-12);
  PortCommand out;
  out.depth = -1;  // pulled far out: the tip stops 5 mm inside the port
  EXPECT_NEAR((k.pose(out).translation - kPivot).norm(), 0.005, 1e-12);
}

TEST(PortDevice, ReadsWhatTheUiSetOnlyWhileOpen) {
  PortDevice d(PortKinematics(kStart, Vec3(0, 0, 1), kPivot));
  DeviceInput in;
  EXPECT_EQ(d.read(0, in), DeviceStatus::kDisconnected);
  d.open();
  PortCommand c;
  c.depth = 0.02;
  c.jaw = 1;
  d.set(c);
  EXPECT_EQ(d.read(0, in), DeviceStatus::kConnected);
  EXPECT_NEAR(in.pose.translation.z(), 0.03, 1e-12);
  EXPECT_EQ(in.jaw, 1);
  EXPECT_EQ(d.specs().max_force, 0);
  EXPECT_EQ(d.counters().samples, 2u);  // the start pose and this one
  EXPECT_NEAR((default_port(kStart, Vec3(0, 0, 0.1)) - Vec3(0, 0, 0.11)).norm(), 0, 1e-12);
}

}  // namespace
}  // namespace trocar
