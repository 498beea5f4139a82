#include "trocar/device/openigtlink_device.h"

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

struct OpenIgtLinkDevice::Sockets {
  igtl::ServerSocket::Pointer server;
  igtl::ClientSocket::Pointer client;
};

namespace {

constexpr std::uint64_t kMaxBody = 1 << 20;  // a larger body announces a garbage header

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

bool orthonormal(const Mat3& r) { return (r * r.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-3; }

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
  sockets_->server = igtl::ServerSocket::New();
  if (sockets_->server->CreateServer(settings_.port) < 0) {
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
    bool accepted = false;
    Pose pose;
    const auto read_body = [&](igtl::MessageBase* m) -> Io {
      m->SetMessageHeader(header);
      m->AllocatePack();
      return receive_exact(client, m->GetPackBodyPointer(), m->GetPackBodySize(), stop_);
    };
    if (type == "TRANSFORM") {
      igtl::TransformMessage::Pointer m = igtl::TransformMessage::New();
      const Io b = read_body(m);
      if (b == Io::kStopped) break;
      if (b == Io::kClosed) {
        drop_client();
        continue;
      }
      if (m->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) {
        igtl::Matrix4x4 t;
        m->GetMatrix(t);
        Mat3 r;
        Vec3 p;
        bool finite = true;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) r(i, j) = t[i][j];
          p[i] = t[i][3] * 1e-3;  // mm → m
        }
        finite = r.allFinite() && p.allFinite();
        if (finite && orthonormal(r)) {
          pose.rotation = Quat(r).normalized();
          pose.translation = p;
          accepted = true;
        }
      }
    } else if (type == "POSITION") {
      igtl::PositionMessage::Pointer m = igtl::PositionMessage::New();
      const Io b = read_body(m);
      if (b == Io::kStopped) break;
      if (b == Io::kClosed) {
        drop_client();
        continue;
      }
      if (m->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) {
        float pos[3], q[4];
        m->GetPosition(pos);
        m->GetQuaternion(q);
        const Vec3 p(pos[0] * 1e-3, pos[1] * 1e-3, pos[2] * 1e-3);
        const Quat quat(q[3], q[0], q[1], q[2]);
        const double norm = quat.norm();
        if (p.allFinite() && std::isfinite(norm) && norm > 1e-6) {
          pose.rotation = quat.normalized();
          pose.translation = p;
          accepted = true;
        }
      }
    } else {
      if (body > 0 && client->Skip(static_cast<int>(body)) == 0) {
        malformed_.fetch_add(1);
        drop_client();
        continue;
      }
    }
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
