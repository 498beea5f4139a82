#include "trocar/device/openigtlink_device.h"

#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlPositionMessage.h>
#include <igtlSensorMessage.h>
#include <igtlServerSocket.h>
#include <igtlTransformMessage.h>
#include <igtlUnit.h>
#pragma GCC diagnostic pop

#include "trocar/core/error.h"

namespace trocar {

namespace {

// igtl::ServerSocket binds without SO_REUSEADDR: after a close() with a client connected, the
// port stays taken while the old connection sits in FIN-WAIT/TIME-WAIT (about a minute) and a
// reopen fails. This one sets it (a second listener on the port is still refused).
class ReusableServerSocket : public igtl::ServerSocket {
 public:
  typedef igtl::SmartPointer<ReusableServerSocket> Pointer;
  static Pointer make() {
    Pointer p = new ReusableServerSocket;
    p->UnRegister();  // igtl objects start with one reference; the smart pointer holds it now
    return p;
  }
  /// Like CreateServer(port): 0 on success, -1 on failure.
  int listen_on(int port) {
    m_SocketDescriptor = CreateSocket();
    if (m_SocketDescriptor < 0) return -1;
    const int on = 1;
    setsockopt(m_SocketDescriptor, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (BindSocket(m_SocketDescriptor, port) != 0 || Listen(m_SocketDescriptor) != 0) {
      CloseSocket();
      return -1;
    }
    return 0;
  }
};

}  // namespace

struct OpenIgtLinkDevice::Sockets {
  ReusableServerSocket::Pointer server;
  igtl::ClientSocket::Pointer client;
};

namespace {

constexpr std::uint64_t kMaxBody = 1 << 20;  // a larger body announces a garbage header
constexpr std::uint64_t kTransformBody = 48;  // 12 float32: the 3×3 rotation, then translation
constexpr std::uint64_t kPositionBody = 28;   // 7 float32: position, quaternion x, y, z, w

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

enum class Io { kDone, kClosed, kStopped };

// Reads n bytes, retrying on the socket's short receive timeout until done, the peer closes, or
// the driver stops.
Io receive_exact(igtl::ClientSocket* s, void* data, int n, const std::atomic<bool>& stop) {
  auto* p = static_cast<char*>(data);
  int got = 0;
  while (got < n) {
    if (stop.load()) return Io::kStopped;
    const int r = s->Receive(p + got, n - got, 0);
    if (r == 0) return Io::kClosed;
    if (r < 0) continue;  // timeout
    got += r;
  }
  return Io::kDone;
}

// Reads and drops n bytes (igtl's Skip() miscounts on the receive timeout and desyncs the stream).
Io skip_exact(igtl::ClientSocket* s, std::uint64_t n, const std::atomic<bool>& stop) {
  char scratch[4096];
  while (n > 0) {
    const int chunk = static_cast<int>(std::min<std::uint64_t>(n, sizeof scratch));
    const Io r = receive_exact(s, scratch, chunk, stop);
    if (r != Io::kDone) return r;
    n -= static_cast<std::uint64_t>(chunk);
  }
  return Io::kDone;
}

bool orthonormal(const Mat3& r) { return (r * r.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-3; }

// An unpacked TRANSFORM as a pose (mm → m); false for non-finite values or a rotation that is
// not orthonormal.
bool transform_pose(igtl::TransformMessage& m, Pose& pose) {
  igtl::Matrix4x4 t;
  m.GetMatrix(t);
  Mat3 r;
  Vec3 p;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = t[i][j];
    p[i] = t[i][3] * 1e-3;
  }
  if (!r.allFinite() || !p.allFinite() || !orthonormal(r)) return false;
  pose.rotation = Quat(r).normalized();
  pose.translation = p;
  return true;
}

// An unpacked POSITION as a pose (mm → m, quaternion x, y, z, w normalised); false for
// non-finite values or a (near) zero quaternion.
bool position_pose(igtl::PositionMessage& m, Pose& pose) {
  float pos[3], q[4];
  m.GetPosition(pos);
  m.GetQuaternion(q);
  const Vec3 p(pos[0] * 1e-3, pos[1] * 1e-3, pos[2] * 1e-3);
  const Quat quat(q[3], q[0], q[1], q[2]);
  const double norm = quat.norm();
  if (!p.allFinite() || !std::isfinite(norm) || !(norm > 1e-6)) return false;
  pose.rotation = quat.normalized();
  pose.translation = p;
  return true;
}

}  // namespace

OpenIgtLinkDevice::OpenIgtLinkDevice(const OpenIgtLinkSettings& settings) : settings_(settings) {
  specs_.name = "openigtlink :" + std::to_string(settings.port);
  specs_.max_force = settings.max_force;
  specs_.damping = settings.damping;
  specs_.workspace = settings.workspace;
}

OpenIgtLinkDevice::~OpenIgtLinkDevice() { close(); }

void OpenIgtLinkDevice::open() {
  if (sockets_) return;
  sockets_ = new Sockets;
  sockets_->server = ReusableServerSocket::make();
  if (sockets_->server->listen_on(settings_.port) < 0) {
    delete sockets_;
    sockets_ = nullptr;
    throw Error("openigtlink: cannot listen on TCP port " + std::to_string(settings_.port) + " (in use?)");
  }
  bound_port_ = sockets_->server->GetServerPort();
  specs_.name = "openigtlink :" + std::to_string(bound_port_);
  stop_ = false;
  thread_ = std::thread([this] { serve(); });
}

void OpenIgtLinkDevice::close() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (sockets_) {
    if (sockets_->client) sockets_->client->CloseSocket();
    sockets_->server->CloseSocket();
    delete sockets_;
    sockets_ = nullptr;
  }
  connected_ = false;
}

void OpenIgtLinkDevice::serve() {
  igtl::MessageHeader::Pointer header = igtl::MessageHeader::New();
  igtl::TransformMessage::Pointer transform = igtl::TransformMessage::New();  // reused per message
  igtl::PositionMessage::Pointer position = igtl::PositionMessage::New();
  igtl::SensorMessage::Pointer sensor = igtl::SensorMessage::New();
  igtl::Unit::Pointer newton = igtl::Unit::New();
  newton->SetPrefix(igtl::Unit::SI_PREFIX_NONE);
  newton->Append(igtl::Unit::SI_DERIVED_NEWTON, 1);
  Pose last_pose;
  std::int64_t last_ns = 0;
  std::uint64_t sequence = 0;
  const auto drop_client = [&] {
    sockets_->client->CloseSocket();
    sockets_->client = nullptr;
    connected_ = false;
  };
  while (!stop_.load()) {
    if (!sockets_->client) {
      igtl::ClientSocket::Pointer c = sockets_->server->WaitForConnection(50);
      if (c.IsNull()) continue;
      c->SetReceiveTimeout(20);
      sockets_->client = c;
      connections_.fetch_add(1);
      connect_sequence_ = sequence;  // before connected_: read() sees it once connected
      connected_ = true;
      last_ns = 0;
      continue;
    }
    igtl::ClientSocket* client = sockets_->client;
    header->InitPack();
    const Io h = receive_exact(client, header->GetPackPointer(), header->GetPackSize(), stop_);
    if (h == Io::kStopped) break;
    if (h == Io::kClosed) {
      drop_client();
      continue;
    }
    header->Unpack();
    const auto body = static_cast<std::uint64_t>(header->GetBodySizeToRead());
    if (body > kMaxBody) {
      malformed_.fetch_add(1);
      drop_client();
      continue;
    }
    const std::string type = header->GetDeviceType();
    const std::uint64_t expected = type == "TRANSFORM" ? kTransformBody : type == "POSITION" ? kPositionBody : 0;
    if (body != expected) {  // another type, or a body of the wrong size: skipped whole
      const Io b = skip_exact(client, body, stop_);
      if (b == Io::kStopped) break;
      malformed_.fetch_add(1);
      if (b == Io::kClosed) drop_client();
      continue;
    }
    const bool is_transform = type == "TRANSFORM";
    igtl::MessageBase* m = is_transform ? static_cast<igtl::MessageBase*>(transform) : position;
    m->SetMessageHeader(header);
    m->AllocatePack();
    const Io b = receive_exact(client, m->GetPackBodyPointer(), m->GetPackBodySize(), stop_);
    if (b == Io::kStopped) break;
    if (b == Io::kClosed) {
      drop_client();
      continue;
    }
    Pose pose;
    const bool accepted = (m->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) &&
                          (is_transform ? transform_pose(*transform, pose) : position_pose(*position, pose));
    if (!accepted) {
      malformed_.fetch_add(1);
      continue;
    }
    const std::int64_t now = steady_ns();
    DeviceInput in;
    in.pose = pose;
    const double span = last_ns ? double(now - last_ns) * 1e-9 : 0;
    in.velocity = span > 0 ? Vec3((pose.translation - last_pose.translation) / span) : Vec3::Zero();
    in.timestamp_ns = now;
    in.sequence = ++sequence;
    sample_.publish(in);
    samples_.fetch_add(1);
    last_pose = pose;
    last_ns = now;

    DeviceOutput out;
    force_.read(out);
    sensor->SetDeviceName(settings_.device_name.c_str());
    sensor->SetLength(3);
    sensor->SetUnit(newton);
    for (unsigned i = 0; i < 3; ++i) sensor->SetValue(i, out.force[static_cast<int>(i)]);
    sensor->Pack();
    if (client->Send(sensor->GetPackPointer(), sensor->GetPackSize()) != 0) forces_sent_.fetch_add(1);
  }
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
  c.forces_sent = forces_sent_.load();
  return c;
}

}  // namespace trocar
