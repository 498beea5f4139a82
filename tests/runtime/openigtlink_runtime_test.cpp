// End to end: an OpenIGTLink client (built from the library, over loopback) drives the shipped
// press scene's probe on the runtime, presses the lobe, receives the rendered force, drops the
// connection mid-press and comes back still pressing. The haptic loop ticks on through the drop,
// the force stays off after reconnecting until the hand backs off (safe start), then returns, and
// the report warns. The runtime runs on a manual clock: one pose, then one haptic period.
#include <gtest/gtest.h>

#ifdef TROCAR_HAVE_OPENIGTLINK
#include <chrono>
#include <filesystem>
#include <functional>
#include <thread>

#include "support/igtl_client.h"
#include "support/manual_clock.h"

#include "trocar/device/openigtlink_device.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

constexpr std::int64_t kPeriod = 1000000;  // ns: 1 kHz

/// Polls `pred` up to 10 s of wall time (a connection or a drop crossing the loopback).
template <typename Pred>
bool wait_for(Pred pred) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return pred();
}

struct Client {
  igtl::ClientSocket::Pointer socket = igtl::ClientSocket::New();
  double max_force = 0;       ///< |F| of the SENSOR replies (N)
  double first_force = -1;    ///< |F| of the first reply of this connection
  int replies = 0;

  bool connect(int port) {
    if (socket->ConnectToServer("127.0.0.1", port) != 0) return false;
    socket->SetReceiveTimeout(10000);  // the reply follows the pose at once; 10 s for a busy machine
    return true;
  }
  // Sends the probe's pose (z in mm, the press scene's frame) and reads the SENSOR reply.
  void exchange(double z_mm) {
    igtl::TransformMessage::Pointer m = igtl::TransformMessage::New();
    m->SetDeviceName("probe");
    igtl::Matrix4x4 t;
    igtl::IdentityMatrix(t);
    t[2][3] = static_cast<float>(z_mm);
    m->SetMatrix(t);
    m->Pack();
    socket->Send(m->GetPackPointer(), m->GetPackSize());
    igtl::MessageHeader::Pointer h = igtl::MessageHeader::New();
    h->InitPack();
    if (socket->Receive(h->GetPackPointer(), h->GetPackSize()) != h->GetPackSize()) return;
    h->Unpack();
    igtl::SensorMessage::Pointer s = igtl::SensorMessage::New();
    s->SetMessageHeader(h);
    s->AllocatePack();
    if (socket->Receive(s->GetPackBodyPointer(), s->GetPackBodySize()) != s->GetPackBodySize()) return;
    if (!(s->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) || s->GetLength() != 3) return;
    const double f = Vec3(s->GetValue(0), s->GetValue(1), s->GetValue(2)).norm();
    if (first_force < 0) first_force = f;
    max_force = std::max(max_force, f);
    ++replies;
  }
};

TEST(OpenIgtLinkRuntime, ClientPressesFeelsForceDropsAndReconnects) {
  Scene scene = load_scene(std::filesystem::path(TROCAR_TEST_SCENES) / "probe_press_slide.json");
  scene.settings.measure_penetration = false;
  Simulation sim(std::move(scene.world), scene.settings);
  OpenIgtLinkSettings s;
  s.port = 0;
  s.stale_after_s = 600;  // poses are as old as the test's pace on this machine, not the clock's
  auto device = std::make_unique<OpenIgtLinkDevice>(s);
  device->open();
  OpenIgtLinkDevice& server = *device;
  const int port = device->port();
  std::vector<RuntimeChannel> channels(1);
  channels[0].device = std::move(device);
  channels[0].where = "test";
  test::ManualClock clock;
  RuntimeSettings settings;
  settings.duration = 0;  // until request_stop
  settings.realtime_scheduling = false;
  settings.clock = &clock;
  Runtime runtime(sim, std::move(channels), settings);
  RuntimeReport report;
  std::thread runner([&] { report = runtime.run(); });
  struct StopOnExit {  // a failed ASSERT leaves with the runtime still running
    std::function<void()> stop;
    ~StopOnExit() { stop(); }
  } stop_on_exit{[&] { test::stop_and_join(runtime, clock, runner, kPeriod); }};
  const auto periods = [&](int n) {
    for (int i = 0; i < n; ++i) {
      clock.advance(kPeriod);
      if (!clock.settle(2)) return false;
    }
    return true;
  };
  ASSERT_TRUE(clock.settle(2)) << "the runtime's loops did not reach their start";
  clock.advance(clock.next_deadline() - clock.now_ns());
  ASSERT_TRUE(clock.settle(2));

  // 45 mm → 20 mm over 800 ticks (the lobe's top is near 30 mm), then hold: a pose every tick.
  Client before, after;
  ASSERT_TRUE(before.connect(port));
  for (int k = 0; k < 1000; ++k) {
    before.exchange(45 - 25 * std::min(1.0, k / 800.0));
    ASSERT_TRUE(periods(1)) << "tick " << k;
  }
  before.socket->CloseSocket();
  DeviceInput in;
  ASSERT_TRUE(wait_for([&] { return server.read(0, in) == DeviceStatus::kDisconnected; })) << "the drop was not seen";
  // The haptic loop never waits on the network: each period of the drop is one tick.
  const std::uint64_t ticks_at_drop = runtime.live().ticks.load();
  ASSERT_TRUE(periods(300));
  EXPECT_EQ(runtime.live().ticks.load(), ticks_at_drop + 300);

  // Back while pressed (force held off), withdraw (the safe start engages), press again.
  ASSERT_TRUE(after.connect(port));
  ASSERT_TRUE(wait_for([&] { return server.counters().connections == 2; }));
  for (int k = 0; k < 900; ++k) {
    const double u = k / 1000.0;
    after.exchange(u < 0.2 ? 20 : u < 0.4 ? 20 + 25 * (u - 0.2) / 0.2 : 45 - 25 * std::min(1.0, (u - 0.4) / 0.4));
    ASSERT_TRUE(periods(1)) << "tick " << k << " after the reconnect";
  }
  ASSERT_TRUE(test::stop_and_join(runtime, clock, runner, kPeriod)) << "run() did not end within 30 s of request_stop";
  after.socket->CloseSocket();  // after the stop: the one drop counted is the first client's

  EXPECT_EQ(before.replies, 1000) << "every pose is answered";
  EXPECT_GT(before.max_force, 0.2) << "the press must be felt";
  EXPECT_LE(before.max_force, 3.3 + 1e-9) << "clamped to the device's maximum";
  EXPECT_EQ(after.replies, 900);
  EXPECT_LT(after.first_force, 0.05) << "after a reconnect the force starts from zero (safe start)";
  EXPECT_GT(after.max_force, 0.2) << "and comes back once the hand backed off and pressed again";
  EXPECT_EQ(report.disconnects, 1u);
  EXPECT_EQ(report.devices[0].counters.connections, 2u);
  // One tick per period from the start to the stop (+1 each), none late: the drop cost no tick.
  EXPECT_EQ(report.ticks, 1u + 1000u + 300u + 900u + 1u);
  EXPECT_EQ(report.deadline_miss_fraction, 0.0);
  bool warned = false;
  for (const std::string& w : report.warnings) warned |= w.find("dropped") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace trocar
#else
TEST(OpenIgtLinkRuntime, NotBuilt) { GTEST_SKIP() << "libopenigtlink-dev was not found at configure time"; }
#endif
