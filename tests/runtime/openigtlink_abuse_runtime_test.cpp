// The openigtlink driver under abuse on the runtime (tests/support/igtl_abuse.h): after 100
// connect/drop cycles, garbage, a 2^62-byte header, NaN transforms with bad CRCs and half a
// header then silence, a well-behaved client's last pose is where physics puts the instrument,
// and the run's report holds the device's exact counters.
#include <gtest/gtest.h>

#ifdef TROCAR_HAVE_OPENIGTLINK
#include <filesystem>
#include <thread>

#include "support/igtl_abuse.h"

#include "trocar/device/openigtlink_device.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

TEST(OpenIgtLinkAbuseRuntime, AWellBehavedClientDrivesTheInstrumentAndTheReportCountsItAll) {
  Scene scene = load_scene(std::filesystem::path(TROCAR_TEST_SCENES) / "probe_press_slide.json");
  scene.settings.measure_penetration = false;
  Simulation sim(std::move(scene.world), scene.settings);
  OpenIgtLinkSettings s;
  s.port = 0;
  s.stale_after_s = 60;  // the client pauses while the test checks; its pose must not go stale
  auto owned = std::make_unique<OpenIgtLinkDevice>(s);
  OpenIgtLinkDevice& device = *owned;
  device.open();
  std::vector<RuntimeChannel> channels(1);
  channels[0].device = std::move(owned);
  channels[0].where = "test";
  RuntimeSettings settings;
  settings.duration = 0;  // until request_stop()
  settings.lockstep = true;
  settings.realtime_scheduling = false;
  Runtime runtime(sim, std::move(channels), settings);

  int good = -1;
  bool steered = false;
  std::thread client([&] {
    good = igtl_abuse::run(device.port(), [&] { return device.counters(); });
    // The good pose is in; once the loop has run some ticks after it, physics has taken it.
    const std::uint64_t ticks = runtime.live().ticks.load();
    steered = igtl_abuse::eventually([&] { return runtime.live().ticks.load() > ticks + 10; });
    runtime.request_stop();
  });
  const RuntimeReport report = runtime.run();
  client.join();
  if (good >= 0) ::close(good);
  ASSERT_TRUE(steered);

  // Device frame = world (no mapping); mm → m.
  const Pose& pose = sim.world().instruments[0].instrument.pose();
  EXPECT_NEAR((pose.translation - Vec3(0.010, -0.020, 0.030)).norm(), 0, 1e-9);
  const Quat expected(Eigen::AngleAxisd(igtl_abuse::kGoodAngle, Vec3::UnitZ()));
  EXPECT_NEAR(pose.rotation.angularDistance(expected), 0, 1e-6);

  ASSERT_EQ(report.devices.size(), 1u);
  const DeviceReport& d = report.devices[0];
  const igtl_abuse::Expected e;
  EXPECT_EQ(d.name, "openigtlink :" + std::to_string(device.port()));
  EXPECT_EQ(d.counters.connections, e.connections);
  EXPECT_EQ(d.counters.drops, e.drops);
  EXPECT_EQ(d.counters.malformed, e.malformed);
  EXPECT_EQ(d.counters.samples, e.samples);
  EXPECT_EQ(d.counters.forces_sent, e.samples);  // one reply per pose
  EXPECT_LE(d.disconnects, e.drops);  // the loop sees a drop only when it ticks inside the gap
  EXPECT_EQ(report.disconnects, d.disconnects);
}

}  // namespace
}  // namespace trocar
#else
TEST(OpenIgtLinkAbuseRuntime, NotBuilt) { GTEST_SKIP() << "libopenigtlink-dev was not found at configure time"; }
#endif
