// The openigtlink driver under abuse (tests/support/igtl_abuse.h): 100 connect/drop cycles,
// garbage, a 2^62-byte header, NaN transforms with bad CRCs, half a header then silence. After
// all of it a well-behaved client's poses are taken, exactly, and every counter is exact.
#include <gtest/gtest.h>

#ifdef TROCAR_HAVE_OPENIGTLINK
#include "support/igtl_abuse.h"

#include "trocar/device/openigtlink_device.h"

namespace trocar {
namespace {

TEST(OpenIgtLinkAbuse, AfterAllOfItAWellBehavedClientDrivesTheDevice) {
  OpenIgtLinkSettings settings;
  settings.port = 0;
  settings.stale_after_s = 60;  // the pose is checked, not its age
  OpenIgtLinkDevice device(settings);
  device.open();
  device.write({Vec3(0.25, -0.5, 1.0), Vec3::Zero(), 0});
  const int good = igtl_abuse::run(device.port(), [&] { return device.counters(); });
  ASSERT_GE(good, 0);

  DeviceInput in;
  ASSERT_EQ(device.read(0, in), DeviceStatus::kConnected);
  EXPECT_EQ(in.sequence, 3u);
  EXPECT_NEAR((in.pose.translation - Vec3(0.010, -0.020, 0.030)).norm(), 0, 1e-9);  // mm → m
  const Quat expected(Eigen::AngleAxisd(igtl_abuse::kGoodAngle, Vec3::UnitZ()));
  EXPECT_NEAR(in.pose.rotation.angularDistance(expected), 0, 1e-6);  // float32 entries
  EXPECT_NEAR(in.pose.rotation.norm(), 1, 1e-12);

  // Each pose was answered with the force written: 3 SENSOR messages of 58 + 10 + 3·8 bytes.
  std::vector<std::uint8_t> replies(3 * (58 + 10 + 24));
  std::size_t got = 0;
  while (got < replies.size()) {
    const ssize_t n = ::recv(good, replies.data() + got, replies.size() - got, 0);
    ASSERT_GT(n, 0) << "after " << got << " bytes";
    got += static_cast<std::size_t>(n);
  }
  igtl_float64 force[3];
  std::memcpy(force, replies.data() + replies.size() - sizeof force, sizeof force);
  for (igtl_float64& f : force) f = igtl_abuse::from_network(f);
  EXPECT_EQ(force[0], 0.25);
  EXPECT_EQ(force[1], -0.5);
  EXPECT_EQ(force[2], 1.0);
  EXPECT_EQ(device.counters().forces_sent, 3u);
  ::close(good);
  EXPECT_TRUE(igtl_abuse::eventually([&] { return device.read(0, in) == DeviceStatus::kDisconnected; }));
  EXPECT_EQ(device.counters().drops, igtl_abuse::Expected{}.drops + 1);
}

// A client that streams poses and never reads the SENSOR replies: the server's sends would
// block once the socket buffers are full; it skips replies instead and keeps taking poses.
TEST(OpenIgtLinkAbuse, AClientThatNeverReadsTheRepliesDoesNotStallTheServer) {
  OpenIgtLinkSettings settings;
  settings.port = 0;
  OpenIgtLinkDevice device(settings);
  device.open();
  const int deaf = igtl_abuse::connect_to(device.port());
  ASSERT_GE(deaf, 0);
  const std::vector<std::uint8_t> pose = igtl_abuse::transform(Vec3(1, 2, 3), 0);
  constexpr std::uint64_t kPoses = 100000;  // 9.2 MB of replies, far beyond loopback's buffers
  std::vector<std::uint8_t> batch;
  for (int i = 0; i < 1000; ++i) batch.insert(batch.end(), pose.begin(), pose.end());
  for (std::uint64_t i = 0; i < kPoses / 1000; ++i) ASSERT_NO_FATAL_FAILURE(igtl_abuse::send_all(deaf, batch));
  EXPECT_TRUE(igtl_abuse::eventually([&] { return device.counters().samples == kPoses; }))
      << device.counters().samples;
  const DeviceCounters c = device.counters();
  EXPECT_GE(c.forces_sent, 1u);
  EXPECT_LT(c.forces_sent, kPoses);  // the rest were skipped, not waited for
  // And the server still takes the next client.
  const int next = igtl_abuse::connect_to(device.port());
  igtl_abuse::send_all(next, igtl_abuse::transform(Vec3(7, 8, 9), 0));
  EXPECT_TRUE(igtl_abuse::eventually([&] { return device.counters().samples == kPoses + 1; }));
  EXPECT_EQ(device.counters().connections, 2u);
  EXPECT_EQ(device.counters().drops, 1u);
  DeviceInput in;
  device.read(0, in);
  EXPECT_NEAR((in.pose.translation - Vec3(0.007, 0.008, 0.009)).norm(), 0, 1e-9);
  ::close(deaf);
  ::close(next);
}

}  // namespace
}  // namespace trocar
#else
TEST(OpenIgtLinkAbuse, NotBuilt) { GTEST_SKIP() << "libopenigtlink-dev was not found at configure time"; }
#endif
