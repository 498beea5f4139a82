#include "trocar/device/openigtlink_parser.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#include <igtl_header.h>
#include <igtl_position.h>
#include <igtl_transform.h>
#include <igtl_util.h>
#pragma GCC diagnostic pop

namespace trocar {

namespace {

static_assert(sizeof(igtl_header) == IgtlStreamParser::kHeaderSize);
constexpr std::size_t kTransformBody = IGTL_TRANSFORM_SIZE;               // 12 float32
constexpr std::size_t kPositionBody = IGTL_POSITION_MESSAGE_DEFAULT_SIZE;  // 7 float32

// The header's type name equals `type` (the field is 0-padded, not 0-terminated when full).
bool type_is(const igtl_header& h, const char* type) {
  return std::strncmp(h.name, type, IGTL_HEADER_TYPE_SIZE) == 0;
}

bool orthonormal(const Mat3& r) { return (r * r.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-3; }

// TRANSFORM body (network order) as a pose, mm → m; false for non-finite values or a rotation
// that is not orthonormal. Element i + 3j is the matrix's row i, column j (igtl_transform.h).
bool transform_pose(const std::uint8_t* body, Pose& pose) {
  igtl_float32 t[12];
  std::memcpy(t, body, sizeof t);
  igtl_transform_convert_byte_order(t);
  Mat3 r;
  Vec3 p;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = t[i + 3 * j];
    p[i] = t[i + 9] * 1e-3;
  }
  if (!r.allFinite() || !p.allFinite() || !orthonormal(r)) return false;
  pose.rotation = Quat(r).normalized();
  pose.translation = p;
  return true;
}

// POSITION body (network order) as a pose, mm → m, quaternion x, y, z, w normalised; false for
// non-finite values or a (near) zero quaternion.
bool position_pose(const std::uint8_t* body, Pose& pose) {
  igtl_position m;
  std::memcpy(&m, body, sizeof m);
  igtl_position_convert_byte_order(&m);
  const Vec3 p(m.position[0] * 1e-3, m.position[1] * 1e-3, m.position[2] * 1e-3);
  const Quat q(m.quaternion[3], m.quaternion[0], m.quaternion[1], m.quaternion[2]);
  const double norm = q.norm();
  if (!p.allFinite() || !std::isfinite(norm) || !(norm > 1e-6)) return false;
  pose.rotation = q.normalized();
  pose.translation = p;
  return true;
}

static_assert(sizeof(igtl_position) == kPositionBody);

}  // namespace

bool IgtlStreamParser::feed(const std::uint8_t* data, std::size_t size, Sink& sink) {
  while (size > 0 && stage_ != Stage::kGarbage) {
    if (stage_ == Stage::kSkip) {
      const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(skip_left_, size));
      skip_left_ -= n;
      data += n, size -= n;
      if (skip_left_ == 0) stage_ = Stage::kHeader;
      continue;
    }
    std::uint8_t* into = stage_ == Stage::kHeader ? header_.data() : body_.data();
    const std::size_t want = stage_ == Stage::kHeader ? kHeaderSize : body_size_;
    const std::size_t n = std::min(want - have_, size);
    std::memcpy(into + have_, data, n);
    have_ += n;
    data += n, size -= n;
    if (have_ < want) break;
    have_ = 0;
    if (stage_ == Stage::kHeader)
      header_done(sink);
    else
      body_done(sink);
  }
  return stage_ != Stage::kGarbage;
}

void IgtlStreamParser::header_done(Sink& sink) {
  igtl_header h;
  std::memcpy(&h, header_.data(), sizeof h);
  igtl_header_convert_byte_order(&h);
  if (h.body_size > kMaxBody) {
    sink.malformed();
    stage_ = Stage::kGarbage;
    return;
  }
  const bool transform = type_is(h, "TRANSFORM"), position = type_is(h, "POSITION");
  const std::size_t expected = transform ? kTransformBody : position ? kPositionBody : 0;
  if (expected == 0 || h.body_size != expected) {  // another type, or a body of the wrong size
    sink.malformed();                              // known now; the body is dropped as it comes
    skip_left_ = h.body_size;
    stage_ = skip_left_ > 0 ? Stage::kSkip : Stage::kHeader;
    return;
  }
  kind_ = transform ? Kind::kTransform : Kind::kPosition;
  body_size_ = expected;
  crc_ = h.crc;
  stage_ = Stage::kBody;
}

void IgtlStreamParser::body_done(Sink& sink) {
  stage_ = Stage::kHeader;
  Pose pose;
  const bool crc_ok = crc64(body_.data(), body_size_, 0) == crc_;
  const bool ok = crc_ok && (kind_ == Kind::kTransform ? transform_pose(body_.data(), pose)
                                                       : position_pose(body_.data(), pose));
  if (ok)
    sink.pose(pose);
  else
    sink.malformed();
}

void IgtlStreamParser::finish(Sink& sink) {
  // Part of a header, or of a body taken: not yet reported. A skipped body or garbage was.
  if ((stage_ == Stage::kHeader && have_ > 0) || stage_ == Stage::kBody) sink.malformed();
  reset();
}

}  // namespace trocar
