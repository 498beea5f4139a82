#include "trocar/device/openigtlink_device.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <igtlSensorMessage.h>
#include <igtlUnit.h>
#pragma GCC diagnostic pop

#include "trocar/core/error.h"
#include "trocar/device/openigtlink_parser.h"

namespace trocar {

namespace {

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

// The socket thread's state and loop. Plain POSIX sockets, polled together with the listener so
// that a new client is accepted at once even while another is connected (the newest wins), with
// a full backlog; sends never block and never raise SIGPIPE (MSG_NOSIGNAL | MSG_DONTWAIT).
struct OpenIgtLinkDevice::Sockets final : IgtlStreamParser::Sink {
  OpenIgtLinkDevice& device;
  int listener = -1;
  int wake = -1;    // eventfd: close() writes it to end the loop at once
  int client = -1;
  IgtlStreamParser parser;
  std::vector<std::uint8_t> out;  // the last SENSOR reply; bytes before out_sent have gone
  std::size_t out_sent = 0;
  igtl::SensorMessage::Pointer sensor = igtl::SensorMessage::New();
  Pose last_pose;
  std::int64_t last_ns = 0;
  std::uint64_t sequence = 0;

  explicit Sockets(OpenIgtLinkDevice& d) : device(d) {
    igtl::Unit::Pointer newton = igtl::Unit::New();
    newton->SetPrefix(igtl::Unit::SI_PREFIX_NONE);
    newton->Append(igtl::Unit::SI_DERIVED_NEWTON, 1);
    sensor->SetDeviceName(d.settings_.device_name.c_str());
    sensor->SetLength(3);
    sensor->SetUnit(newton);
  }
  ~Sockets() override {
    close_fd(client);
    close_fd(listener);
    close_fd(wake);
  }
  Sockets(const Sockets&) = delete;
  Sockets& operator=(const Sockets&) = delete;

  // Binds `port` on every interface with SO_REUSEADDR (a reopen right after a close with a
  // client must not wait out TIME-WAIT; a second listener is still refused).
  void listen_on(int port) {
    listener = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    const int on = 1;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_ANY);
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    socklen_t len = sizeof addr;
    if (listener < 0 || ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) != 0 ||
        ::bind(listener, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(listener, SOMAXCONN) != 0 ||
        ::getsockname(listener, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
      throw Error("openigtlink: cannot listen on TCP port " + std::to_string(port) + " (" + std::strerror(errno) +
                  ")");
    device.bound_port_ = ntohs(addr.sin_port);
    wake = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (wake < 0) throw Error(std::string("openigtlink: eventfd failed (") + std::strerror(errno) + ")");
  }

  void serve() {
    bool accept_paused = false;  // accept failed for want of resources: retry after a pause
    while (true) {
      pollfd fds[3] = {{wake, POLLIN, 0}, {accept_paused ? -1 : listener, POLLIN, 0}, {client, POLLIN, 0}};
      if (client >= 0 && out_sent < out.size()) fds[2].events |= POLLOUT;
      if (::poll(fds, 3, accept_paused ? 50 : -1) < 0) continue;  // EINTR
      if (fds[0].revents) return;
      if (fds[2].revents & POLLOUT) flush();
      if (fds[2].revents & (POLLIN | POLLHUP | POLLERR)) receive();
      accept_paused = !accept_all();
    }
  }

  // Takes every pending connection; each replaces the current client. False when accept failed
  // for want of descriptors or memory (the listener stays; the loop retries shortly).
  bool accept_all() {
    while (true) {
      const int fd = ::accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EINTR || errno == ECONNABORTED || errno == EPROTO) continue;
        return errno == EAGAIN || errno == EWOULDBLOCK;
      }
      if (client >= 0) receive();      // what the old client sent before it was replaced counts
      if (client >= 0) drop_client();  // the newest wins
      const int on = 1;
      ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
      client = fd;
      out.clear();
      out_sent = 0;
      last_ns = 0;
      device.connections_.fetch_add(1);
      device.connect_sequence_ = sequence;  // before connected_: read() sees it once connected
      device.connected_ = true;
    }
  }

  // Reads what the client sent (a bounded amount, so that a flood cannot starve the listener).
  void receive() {
    std::uint8_t buffer[4096];
    for (int chunk = 0; chunk < 16 && client >= 0; ++chunk) {
      const ssize_t n = ::recv(client, buffer, sizeof buffer, 0);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
      if (n <= 0) return drop_client();  // the peer closed (0), or reset the connection
      if (!parser.feed(buffer, static_cast<std::size_t>(n), *this)) return drop_client();  // garbage
    }
  }

  // Ends the current connection (peer gone, garbage, or replaced); an unfinished message counts
  // as malformed.
  void drop_client() {
    parser.finish(*this);
    close_fd(client);
    device.connected_ = false;
    device.drops_.fetch_add(1);
  }

  void malformed() override { device.malformed_.fetch_add(1); }

  void pose(const Pose& pose) override {
    const std::int64_t now = steady_ns();
    DeviceInput in;
    in.pose = pose;
    const double span = last_ns ? double(now - last_ns) * 1e-9 : 0;
    in.velocity = span > 0 ? Vec3((pose.translation - last_pose.translation) / span) : Vec3::Zero();
    in.timestamp_ns = now;
    in.sequence = ++sequence;
    device.sample_.publish(in);
    device.samples_.fetch_add(1);
    last_pose = pose;
    last_ns = now;
    reply();
  }

  // Sends the force as a SENSOR message, unless the previous reply has not gone yet.
  void reply() {
    if (client < 0 || out_sent < out.size()) return;
    DeviceOutput force;
    device.force_.read(force);
    for (unsigned i = 0; i < 3; ++i) sensor->SetValue(i, force.force[static_cast<int>(i)]);
    sensor->Pack();
    const auto* bytes = static_cast<const std::uint8_t*>(sensor->GetPackPointer());
    out.assign(bytes, bytes + sensor->GetPackSize());
    out_sent = 0;
    flush();
  }

  void flush() {
    while (out_sent < out.size()) {
      const ssize_t n = ::send(client, out.data() + out_sent, out.size() - out_sent, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;  // the rest when writable
      if (n < 0) {  // the peer is gone: receive() sees it and drops the connection
        out.clear();
        out_sent = 0;
        return;
      }
      out_sent += static_cast<std::size_t>(n);
    }
    device.forces_sent_.fetch_add(1);
  }
};

OpenIgtLinkDevice::OpenIgtLinkDevice(const OpenIgtLinkSettings& settings) : settings_(settings) {
  specs_.name = "openigtlink :" + std::to_string(settings.port);
  specs_.max_force = settings.max_force;
  specs_.damping = settings.damping;
  specs_.workspace = settings.workspace;
}

OpenIgtLinkDevice::~OpenIgtLinkDevice() { close(); }

void OpenIgtLinkDevice::open() {
  if (sockets_) return;
  auto sockets = std::make_unique<Sockets>(*this);
  sockets->listen_on(settings_.port);
  sockets_ = std::move(sockets);
  specs_.name = "openigtlink :" + std::to_string(bound_port_);
  thread_ = std::thread([this] { sockets_->serve(); });
}

void OpenIgtLinkDevice::close() {
  if (!sockets_) return;
  const std::uint64_t one = 1;
  if (::write(sockets_->wake, &one, sizeof one) < 0) {
    // eventfd writes fail only on counter overflow; the loop is already woken then
  }
  if (thread_.joinable()) thread_.join();
  sockets_.reset();
  connected_ = false;
}

DeviceStatus OpenIgtLinkDevice::read(double /*now_s*/, DeviceInput& input) {
  if (!connected_.load(std::memory_order_acquire)) return DeviceStatus::kDisconnected;
  DeviceInput s;
  sample_.read(s);
  if (s.sequence == 0) return DeviceStatus::kStale;  // connected, nothing yet
  input = s;
  if (s.sequence <= connect_sequence_.load()) return DeviceStatus::kStale;  // a previous client's pose
  const double age = double(steady_ns() - s.timestamp_ns) * 1e-9;
  return age > settings_.stale_after_s ? DeviceStatus::kStale : DeviceStatus::kConnected;
}

void OpenIgtLinkDevice::write(const DeviceOutput& output) { force_.publish(output); }

DeviceCounters OpenIgtLinkDevice::counters() const {
  DeviceCounters c;
  c.samples = samples_.load();
  c.malformed = malformed_.load();
  c.connections = connections_.load();
  c.drops = drops_.load();
  c.forces_sent = forces_sent_.load();
  return c;
}

}  // namespace trocar
