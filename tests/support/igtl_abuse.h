#pragma once
// A misbehaving OpenIGTLink client over loopback, then a well-behaved one: the abuse sequence
// the device test and the runtime test both run against the openigtlink driver. Plain POSIX
// sockets (the library's client hides what it sends). Every wait is on a condition with a
// generous deadline; nothing sleeps for a fixed time.
#include <gtest/gtest.h>
#include <endian.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "support/igtl_client.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#include <igtl_transform.h>
#pragma GCC diagnostic pop

#include "trocar/device/device.h"

namespace trocar::igtl_abuse {

/// Waits until pred() holds, polling every millisecond; false after `seconds` (a generous
/// bound: only a broken driver gets there).
template <typename Pred>
bool eventually(Pred pred, double seconds = 10.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!pred()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

/// A blocking loopback connection with 10 s receive and send timeouts (a stalled server fails a
/// test instead of hanging it); -1 if refused.
inline int connect_to(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  const timeval limit{10, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &limit, sizeof limit);
  return fd;
}

inline void send_all(int fd, const std::vector<std::uint8_t>& bytes) {
  ASSERT_EQ(::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL), static_cast<ssize_t>(bytes.size()));
}

/// True when the server closed the connection (recv sees the end; false after 10 s of silence).
inline bool server_closed(int fd) {
  char c;
  while (true) {
    const ssize_t n = ::recv(fd, &c, 1, 0);
    if (n == 0 || (n < 0 && errno == ECONNRESET)) return true;
    if (n < 0) return false;  // the receive timeout
  }
}

/// A version-1 message: header naming `type`, announcing `announced` body bytes, with the CRC of
/// `body` (flipped when `break_crc`), then `body`.
inline std::vector<std::uint8_t> raw_message(const char* type, const std::vector<std::uint8_t>& body,
                                             std::uint64_t announced, bool break_crc = false) {
  igtl_header h{};
  h.version = 1;
  std::memcpy(h.name, type, std::min(std::strlen(type), sizeof h.name));
  std::memcpy(h.device_name, "stylus", 6);
  h.body_size = announced;
  h.crc = crc64(const_cast<std::uint8_t*>(body.data()), body.size(), 0) ^ (break_crc ? 1u : 0u);
  igtl_header_convert_byte_order(&h);
  std::vector<std::uint8_t> bytes(sizeof h + body.size());
  std::memcpy(bytes.data(), &h, sizeof h);
  if (!body.empty()) std::memcpy(bytes.data() + sizeof h, body.data(), body.size());
  return bytes;
}

/// A TRANSFORM: rotation by `angle` about z, translation t (mm); entry [0][0] replaced by
/// `first` when given (NaN), CRC broken on request.
inline std::vector<std::uint8_t> transform(const Vec3& t_mm, double angle, bool break_crc = false,
                                           float first = 0, bool replace_first = false) {
  const auto c = static_cast<float>(std::cos(angle)), s = static_cast<float>(std::sin(angle));
  // Column by column: the rotation's three columns, then the translation (igtl_transform.h).
  igtl_float32 m[12] = {c, s, 0, -s, c, 0, 0, 0, 1, float(t_mm.x()), float(t_mm.y()), float(t_mm.z())};
  if (replace_first) m[0] = first;
  igtl_transform_convert_byte_order(m);
  const auto* p = reinterpret_cast<const std::uint8_t*>(m);
  return raw_message("TRANSFORM", std::vector<std::uint8_t>(p, p + sizeof m), sizeof m, break_crc);
}

/// A float64 as sent (big-endian) in host order.
inline double from_network(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = be64toh(bits);
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

/// What the driver must have counted after the whole sequence.
struct Expected {
  std::uint64_t connections = 105;  // 100 cycles, garbage, 2^62, NaN/CRC, the silent one, the good one
  std::uint64_t drops = 104;        // all but the good client
  std::uint64_t malformed = 8;      // garbage 1, 2^62 1, NaN/CRC 5, the half header 1
  std::uint64_t samples = 3;        // the good client's poses
};

/// The good client's last pose, mm and radians about z.
inline const Vec3 kGoodTranslationMm(10, -20, 30);
constexpr double kGoodAngle = M_PI / 6;

/// Runs the sequence against the server on `port`; `counters` reads the driver's counters.
/// Returns the good client's socket, still open (the caller closes it when done).
inline int run(int port, const std::function<DeviceCounters()>& counters) {
  const auto at = [&](std::uint64_t connections, std::uint64_t drops, std::uint64_t malformed, std::uint64_t samples) {
    return eventually([&] {
      const DeviceCounters c = counters();
      return c.connections == connections && c.drops == drops && c.malformed == malformed && c.samples == samples;
    });
  };
  const auto where = [&] {
    const DeviceCounters c = counters();
    return "connections " + std::to_string(c.connections) + ", drops " + std::to_string(c.drops) + ", malformed " +
           std::to_string(c.malformed) + ", samples " + std::to_string(c.samples);
  };
  // 1. Connect and drop, 100 times as fast as the client can: every connect is taken.
  for (int i = 0; i < 100; ++i) {
    const int fd = connect_to(port);
    EXPECT_GE(fd, 0) << "cycle " << i << ": refused";
    if (fd >= 0) ::close(fd);
  }
  EXPECT_TRUE(at(100, 100, 0, 0)) << where();
  // 2. Garbage: an HTTP request. Its bytes 42..49, read as the body size, announce terabytes: the
  // server counts one malformed message and closes the connection.
  {
    const std::string get = "GET /transform HTTP/1.1\r\nHost: localhost:18944\r\nUser-Agent: abuse\r\n\r\n";
    const int fd = connect_to(port);
    EXPECT_GE(fd, 0);
    send_all(fd, std::vector<std::uint8_t>(get.begin(), get.end()));
    EXPECT_TRUE(server_closed(fd));
    ::close(fd);
  }
  EXPECT_TRUE(at(101, 101, 1, 0)) << where();
  // 3. A header announcing a 2^62-byte body: the same.
  {
    const int fd = connect_to(port);
    send_all(fd, raw_message("TRANSFORM", {}, std::uint64_t{1} << 62));
    EXPECT_TRUE(server_closed(fd));
    ::close(fd);
  }
  EXPECT_TRUE(at(102, 102, 2, 0)) << where();
  // 4. TRANSFORMs with NaN matrices, bad CRCs, or both: 5 dropped, the connection kept.
  {
    const int fd = connect_to(port);
    send_all(fd, transform(Vec3(1, 2, 3), 0, false, NAN, true));
    send_all(fd, transform(Vec3(NAN, 2, 3), 0));
    send_all(fd, transform(Vec3(1, 2, 3), 0, true));
    send_all(fd, transform(Vec3(4, 5, 6), 0.3, true));
    send_all(fd, transform(Vec3(1, 2, 3), 0, true, NAN, true));
    EXPECT_TRUE(at(103, 102, 7, 0)) << where();
    ::close(fd);
  }
  EXPECT_TRUE(at(103, 103, 7, 0)) << where();
  // 5. Half a header, then silence; the connection stays open.
  const int silent = connect_to(port);
  {
    const std::vector<std::uint8_t> good = transform(kGoodTranslationMm, kGoodAngle);
    send_all(silent, std::vector<std::uint8_t>(good.begin(), good.begin() + 29));
  }
  EXPECT_TRUE(at(104, 103, 7, 0)) << where();
  // 6. A well-behaved client comes while the silent one holds the server: the newest wins (the
  // silent one is dropped, its half header counted), and its poses are taken.
  const int good = connect_to(port);
  EXPECT_GE(good, 0);
  EXPECT_TRUE(at(105, 104, 8, 0)) << where();
  EXPECT_TRUE(server_closed(silent));
  ::close(silent);
  send_all(good, transform(Vec3(0, 0, 0), 0));
  send_all(good, transform(Vec3(5, 5, 5), 0.1));
  send_all(good, transform(kGoodTranslationMm, kGoodAngle));
  const Expected e;
  EXPECT_TRUE(at(e.connections, e.drops, e.malformed, e.samples)) << where();
  return good;
}

}  // namespace trocar::igtl_abuse
