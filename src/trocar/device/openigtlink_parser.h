#pragma once
/// The byte-stream half of the `openigtlink` driver: turns what a client sends into poses, with
/// no socket (the driver feeds it what it receives; the fuzz target feeds it anything).
///
/// Protocol version 1 (docs/devices.md, "OpenIGTLink"): a 58-byte header (type name, device
/// name, timestamp, body size, CRC-64 of the body), then the body. Taken:
///  - TRANSFORM, a 48-byte body: 12 float32, the 3×3 rotation column by column, then the
///    translation in millimetres. The rotation must be orthonormal within 1e-3.
///  - POSITION, a 28-byte body: position in millimetres, quaternion x, y, z, w (normalised; not
///    near zero).
/// Anything else is malformed: another type or body size (the body is skipped whole), a CRC that
/// does not match, a non-finite value, a rotation that is not one. A header announcing a body
/// over kMaxBody bytes is garbage: nothing after it can be trusted, so the stream ends there.
#include <array>
#include <cstddef>
#include <cstdint>

#include "trocar/core/pose.h"

namespace trocar {

/// Incremental OpenIGTLink parser: bytes may arrive in any pieces. No allocation.
class IgtlStreamParser {
 public:
  static constexpr std::size_t kHeaderSize = 58;
  static constexpr std::uint64_t kMaxBody = std::uint64_t{1} << 20;  ///< larger: a garbage header

  /// Receives what the parser makes of each message, in stream order.
  class Sink {
   public:
    virtual ~Sink() = default;
    /// A message gave this pose (metres, unit rotation, finite).
    virtual void pose(const Pose& pose) = 0;
    /// A message was dropped as malformed (counted once, when that is known).
    virtual void malformed() = 0;
  };

  /// Parses `size` more bytes of the stream. Returns false once the stream is garbage (reported
  /// to the sink as one malformed message): the caller should close the connection; later bytes
  /// are ignored until reset().
  bool feed(const std::uint8_t* data, std::size_t size, Sink& sink);
  /// The stream ended: an unfinished message (part of a header or body) is reported as
  /// malformed unless it already was; then the parser is ready for a new stream.
  void finish(Sink& sink);
  /// Forgets the stream without reporting anything.
  void reset() { *this = IgtlStreamParser(); }

 private:
  enum class Stage : std::uint8_t { kHeader, kBody, kSkip, kGarbage };
  enum class Kind : std::uint8_t { kTransform, kPosition };
  void header_done(Sink& sink);
  void body_done(Sink& sink);

  Stage stage_ = Stage::kHeader;
  Kind kind_ = Kind::kTransform;
  std::array<std::uint8_t, kHeaderSize> header_{};
  std::array<std::uint8_t, 48> body_{};  // the largest body taken (TRANSFORM)
  std::size_t have_ = 0;                 // bytes of the header or body gathered so far
  std::size_t body_size_ = 0;            // body bytes expected (kBody)
  std::uint64_t skip_left_ = 0;          // body bytes still to drop (kSkip)
  std::uint64_t crc_ = 0;                // the header's CRC of the body
};

}  // namespace trocar
