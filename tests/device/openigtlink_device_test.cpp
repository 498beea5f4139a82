// The openigtlink driver against a client built from the same library over loopback: poses in
// (TRANSFORM, POSITION; mm → m), forces back (SENSOR), malformed messages counted and ignored,
// stale and dropped connections, reconnect. Every wait is bounded.
#include <gtest/gtest.h>

#ifdef TROCAR_HAVE_OPENIGTLINK
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <thread>
#include <vector>

#include "support/igtl_client.h"

#include "trocar/core/error.h"
#include "trocar/device/openigtlink_device.h"

namespace trocar {
namespace {

using Clock = std::chrono::steady_clock;

/// Polls `pred` up to `seconds` of wall time: a bound for a busy machine, not a measurement.
template <typename Pred>
bool wait_for(Pred pred, double seconds = 10.0) {
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return pred();
}

struct Server {
  OpenIgtLinkSettings settings;
  std::unique_ptr<OpenIgtLinkDevice> device;
  explicit Server(double stale = 0.5) {
    settings.port = 0;
    settings.stale_after_s = stale;
    device = std::make_unique<OpenIgtLinkDevice>(settings);
    device->open();
  }
  DeviceStatus read(DeviceInput& in) { return device->read(0, in); }
};

igtl::ClientSocket::Pointer connect(int port) {
  igtl::ClientSocket::Pointer c = igtl::ClientSocket::New();
  EXPECT_EQ(c->ConnectToServer("127.0.0.1", port), 0);
  c->SetReceiveTimeout(2000);
  return c;
}

void send_transform(igtl::ClientSocket* c, float tx, float ty, float tz, double angle_z, float nan_or_scale = 1) {
  igtl::TransformMessage::Pointer m = igtl::TransformMessage::New();
  m->SetDeviceName("stylus");
  igtl::Matrix4x4 t;
  igtl::IdentityMatrix(t);
  const auto c0 = static_cast<float>(std::cos(angle_z)), s0 = static_cast<float>(std::sin(angle_z));
  t[0][0] = c0 * nan_or_scale, t[0][1] = -s0, t[1][0] = s0, t[1][1] = c0;
  t[0][3] = tx, t[1][3] = ty, t[2][3] = tz;
  m->SetMatrix(t);
  m->Pack();
  c->Send(m->GetPackPointer(), m->GetPackSize());
}

void send_position(igtl::ClientSocket* c, float x, float y, float z, float qx, float qy, float qz, float qw) {
  igtl::PositionMessage::Pointer m = igtl::PositionMessage::New();
  m->SetDeviceName("stylus");
  m->SetPosition(x, y, z);
  m->SetQuaternion(qx, qy, qz, qw);
  m->Pack();
  c->Send(m->GetPackPointer(), m->GetPackSize());
}

// A version-1 message from raw parts: `announced` body bytes in the header (CRC over `body`),
// then `body` itself — for bodies the library would not build.
void send_raw(igtl::ClientSocket* c, const char* type, std::vector<unsigned char> body, std::uint64_t announced) {
  igtl_header h{};
  h.version = 1;
  std::memcpy(h.name, type, std::min(std::strlen(type), sizeof h.name));  // not 0-terminated when full
  std::memcpy(h.device_name, "stylus", 6);
  h.body_size = announced;
  h.crc = crc64(body.data(), body.size(), 0);
  igtl_header_convert_byte_order(&h);
  c->Send(&h, IGTL_HEADER_SIZE);
  if (!body.empty()) c->Send(body.data(), static_cast<int>(body.size()));
}

TEST(OpenIgtLink, TransformAndPositionMoveTheInstrumentAndForcesComeBack) {
  Server s;
  igtl::ClientSocket::Pointer c = connect(s.device->port());
  DeviceInput in;
  ASSERT_TRUE(wait_for([&] { return s.read(in) != DeviceStatus::kDisconnected; }));
  s.device->write({Vec3(0.5, -1.25, 2.0), Vec3::Zero(), 0});
  send_transform(c, 10, 20, 30, M_PI / 6);
  ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kConnected; }));
  EXPECT_NEAR((in.pose.translation - Vec3(0.01, 0.02, 0.03)).norm(), 0, 1e-9);
  const Quat expect(Eigen::AngleAxisd(M_PI / 6, Vec3::UnitZ()));
  EXPECT_NEAR(in.pose.rotation.angularDistance(expect), 0, 1e-6);  // float matrix entries

  // The SENSOR reply carries the force written (N), under the configured name.
  igtl::MessageHeader::Pointer h = igtl::MessageHeader::New();
  h->InitPack();
  ASSERT_EQ(c->Receive(h->GetPackPointer(), h->GetPackSize()), h->GetPackSize());
  h->Unpack();
  EXPECT_STREQ(h->GetDeviceType(), "SENSOR");
  EXPECT_STREQ(h->GetDeviceName(), "trocar");
  igtl::SensorMessage::Pointer sensor = igtl::SensorMessage::New();
  sensor->SetMessageHeader(h);
  sensor->AllocatePack();
  ASSERT_EQ(c->Receive(sensor->GetPackBodyPointer(), sensor->GetPackBodySize()), sensor->GetPackBodySize());
  ASSERT_TRUE(sensor->Unpack(1) & igtl::MessageHeader::UNPACK_BODY);
  ASSERT_EQ(sensor->GetLength(), 3u);
  EXPECT_DOUBLE_EQ(sensor->GetValue(0), 0.5);
  EXPECT_DOUBLE_EQ(sensor->GetValue(1), -1.25);
  EXPECT_DOUBLE_EQ(sensor->GetValue(2), 2.0);

  send_position(c, -5, 0, 12.5, 0, 0, 0.7071068f, 0.7071068f);  // 90° about z
  ASSERT_TRUE(wait_for([&] { s.read(in); return in.sequence == 2; }));
  EXPECT_NEAR((in.pose.translation - Vec3(-0.005, 0, 0.0125)).norm(), 0, 1e-9);
  EXPECT_NEAR(in.pose.rotation.angularDistance(Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()))), 0, 1e-6);
  EXPECT_EQ(s.device->counters().samples, 2u);
  EXPECT_EQ(s.device->counters().malformed, 0u);
  EXPECT_TRUE(wait_for([&] { return s.device->counters().forces_sent == 2; }));
}

TEST(OpenIgtLink, MalformedMessagesAreCountedAndIgnored) {
  Server s;
  igtl::ClientSocket::Pointer c = connect(s.device->port());
  DeviceInput in;
  send_transform(c, 1, 2, 3, 0);
  ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kConnected; }));
  const Vec3 good = in.pose.translation;

  send_transform(c, NAN, 2, 3, 0);                 // NaN
  send_transform(c, 1, 2, 3, 0, 3.0f);             // not orthonormal
  {                                                // CRC broken: a body byte flipped after packing
    igtl::TransformMessage::Pointer m = igtl::TransformMessage::New();
    m->SetDeviceName("stylus");
    igtl::Matrix4x4 t;
    igtl::IdentityMatrix(t);
    t[0][3] = 50;
    m->SetMatrix(t);
    m->Pack();
    std::vector<unsigned char> bytes(static_cast<unsigned char*>(m->GetPackPointer()),
                                     static_cast<unsigned char*>(m->GetPackPointer()) + m->GetPackSize());
    bytes.back() ^= 0x40;
    c->Send(bytes.data(), static_cast<int>(bytes.size()));
  }
  {                                                // a type the driver does not take
    igtl::StringMessage::Pointer m = igtl::StringMessage::New();
    m->SetDeviceName("note");
    m->SetString("hello");
    m->Pack();
    c->Send(m->GetPackPointer(), m->GetPackSize());
  }
  send_position(c, 1, 1, 1, 0, 0, 0, 0);           // zero quaternion
  ASSERT_TRUE(wait_for([&] { return s.device->counters().malformed == 5; })) << s.device->counters().malformed;
  s.read(in);
  EXPECT_EQ(in.pose.translation, good);            // still the last good pose
  EXPECT_EQ(s.device->counters().samples, 1u);
  send_transform(c, 7, 8, 9, 0);                   // the connection is still up
  ASSERT_TRUE(wait_for([&] { s.read(in); return in.sequence == 2; }));
  EXPECT_NEAR((in.pose.translation - Vec3(0.007, 0.008, 0.009)).norm(), 0, 1e-9);
  EXPECT_EQ(s.device->counters().connections, 1u);
}

TEST(OpenIgtLink, SilenceIsStaleAndADropReconnects) {
  Server s(0.05);
  DeviceInput in;
  EXPECT_EQ(s.read(in), DeviceStatus::kDisconnected);  // no client yet
  {
    igtl::ClientSocket::Pointer c = connect(s.device->port());
    send_transform(c, 1, 2, 3, 0);
    ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kConnected; }));
    EXPECT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kStale; }));  // > 50 ms silent
    c->CloseSocket();
  }
  // The close itself is seen (not the silence: that only makes it stale).
  ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kDisconnected; })) << "the drop was not seen";
  igtl::ClientSocket::Pointer again = connect(s.device->port());
  send_transform(again, 4, 5, 6, 0);
  ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kConnected; }));
  EXPECT_NEAR((in.pose.translation - Vec3(0.004, 0.005, 0.006)).norm(), 0, 1e-9);
  EXPECT_EQ(s.device->counters().connections, 2u);
}

TEST(OpenIgtLink, CloseWithAClientConnectedReturnsPromptly) {
  Server s;
  igtl::ClientSocket::Pointer c = connect(s.device->port());
  DeviceInput in;
  ASSERT_TRUE(wait_for([&] { return s.read(in) != DeviceStatus::kDisconnected; }));
  // close() does not wait for the client to go (it never does here): bounded, not timed.
  std::future<void> closed = std::async(std::launch::async, [&] { s.device->close(); });
  ASSERT_EQ(closed.wait_for(std::chrono::seconds(30)), std::future_status::ready) << "close() waits for the client";
  EXPECT_EQ(s.read(in), DeviceStatus::kDisconnected);
  OpenIgtLinkDevice never_opened(OpenIgtLinkSettings{});  // destroyed without open(): fine
}

TEST(OpenIgtLink, WrongBodySizesAreDroppedAndAGarbageHeaderClosesTheConnection) {
  Server s;
  DeviceInput in;
  {
    igtl::ClientSocket::Pointer c = connect(s.device->port());
    send_transform(c, 1, 2, 3, 0);
    ASSERT_TRUE(wait_for([&] { s.read(in); return in.sequence == 1; }));
    // A TRANSFORM body of 60 bytes (a good 48-byte matrix and 12 more), CRC right.
    igtl::TransformMessage::Pointer m = igtl::TransformMessage::New();
    igtl::Matrix4x4 t;
    igtl::IdentityMatrix(t);
    t[0][3] = 50;
    m->SetMatrix(t);
    m->Pack();
    std::vector<unsigned char> body(static_cast<unsigned char*>(m->GetPackBodyPointer()),
                                    static_cast<unsigned char*>(m->GetPackBodyPointer()) + m->GetPackBodySize());
    body.resize(60, 0);
    send_raw(c, "TRANSFORM", body, body.size());
    send_raw(c, "POSITION", std::vector<unsigned char>(12, 0), 12);  // position only: no rotation
    send_transform(c, 4, 5, 6, 0);
    ASSERT_TRUE(wait_for([&] { s.read(in); return in.sequence == 2; }));
    EXPECT_EQ(s.device->counters().malformed, 2u);
    EXPECT_NEAR((in.pose.translation - Vec3(0.004, 0.005, 0.006)).norm(), 0, 1e-9);
    send_raw(c, "TRANSFORM", {}, std::uint64_t{2} << 20);  // 2 MiB announced: a garbage header
    ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kDisconnected; }));
    EXPECT_EQ(s.device->counters().malformed, 3u);
  }
  igtl::ClientSocket::Pointer again = connect(s.device->port());
  ASSERT_TRUE(wait_for([&] { return s.device->counters().connections == 2; }));
  EXPECT_EQ(s.read(in), DeviceStatus::kStale);  // the last pose is the previous client's
  send_transform(again, 7, 8, 9, 0);
  ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kConnected; }));
  EXPECT_EQ(s.device->counters().connections, 2u);
  EXPECT_EQ(s.device->counters().samples, 3u);
}

TEST(OpenIgtLink, AnUnsupportedBodyArrivingInPiecesIsSkippedWhole) {
  Server s;
  igtl::ClientSocket::Pointer c = connect(s.device->port());
  igtl::StringMessage::Pointer m = igtl::StringMessage::New();
  m->SetDeviceName("note");
  m->SetString(std::string(4000, 'a').c_str());
  m->Pack();
  const auto* bytes = static_cast<const char*>(m->GetPackPointer());
  c->Send(bytes, IGTL_HEADER_SIZE + 100);  // the rest comes after the driver's receive timeout
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  c->Send(bytes + IGTL_HEADER_SIZE + 100, m->GetPackSize() - IGTL_HEADER_SIZE - 100);
  send_transform(c, 42, 0, 0, 0);
  DeviceInput in;
  ASSERT_TRUE(wait_for([&] { s.read(in); return in.sequence == 1; }));
  EXPECT_NEAR(in.pose.translation.x(), 0.042, 1e-9);
  EXPECT_EQ(s.device->counters().malformed, 1u);
}

TEST(OpenIgtLink, ReopensOnTheSamePortRightAfterClosingWithAClient) {
  Server s;
  const int port = s.device->port();
  igtl::ClientSocket::Pointer c = connect(port);
  send_transform(c, 1, 2, 3, 0);
  DeviceInput in;
  ASSERT_TRUE(wait_for([&] { return s.read(in) == DeviceStatus::kConnected; }));
  s.device->close();  // the server side closes first: its end of the connection lingers
  OpenIgtLinkSettings same = s.settings;
  same.port = port;
  OpenIgtLinkDevice reopened(same);
  ASSERT_NO_THROW(reopened.open());
  igtl::ClientSocket::Pointer again = connect(port);
  send_transform(again, 4, 5, 6, 0);
  ASSERT_TRUE(wait_for([&] { return reopened.read(0, in) == DeviceStatus::kConnected; }));
  EXPECT_NEAR((in.pose.translation - Vec3(0.004, 0.005, 0.006)).norm(), 0, 1e-9);
}

TEST(OpenIgtLink, PortInUseIsAClearError) {
  Server s;
  OpenIgtLinkSettings same;
  same.port = s.device->port();
  OpenIgtLinkDevice second(same);
  EXPECT_THROW(second.open(), Error);
}

}  // namespace
}  // namespace trocar
#else
TEST(OpenIgtLink, NotBuilt) { GTEST_SKIP() << "libopenigtlink-dev was not found at configure time"; }
#endif
