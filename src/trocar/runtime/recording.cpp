#include "trocar/runtime/recording.h"

#include <fcntl.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "trocar/core/error.h"
#include "trocar/device/device.h"

namespace trocar {
namespace {

// FNV-1a, 64-bit (Fowler, Noll, Vo: offset basis 14695981039346656037, prime 1099511628211).
// Version 1 files were written with the basis missing its last digit; they still read.
constexpr std::uint64_t kFnvBasis = 14695981039346656037ULL;
constexpr std::uint64_t kVersion1Basis = 1469598103934665603ULL;

std::uint64_t fnv1a(const unsigned char* data, std::size_t n, std::uint64_t basis = kFnvBasis) {
  std::uint64_t h = basis;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= data[i];
    h *= 1099511628211ULL;
  }
  return h;
}

template <typename T>
void put(std::vector<unsigned char>& out, const T& v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + sizeof(T));
}

void put_string(std::vector<unsigned char>& out, const std::string& s) {
  put(out, static_cast<std::uint64_t>(s.size()));
  out.insert(out.end(), s.begin(), s.end());
}

struct BlockHeader {
  char magic[4];
  std::uint32_t records;
  std::uint32_t payload_bytes;
  std::uint32_t reserved;
  std::uint64_t checksum;
};
static_assert(sizeof(BlockHeader) == 24);

}  // namespace

RecordingWriter::RecordingWriter(const std::filesystem::path& file, const RecordingHeader& header,
                                 std::size_t ring_capacity)
    : file_(file), ticks_(ring_capacity), steps_(ring_capacity) {
  fd_ = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw FileError(file.string(), FileLocation::none(), std::string("cannot create: ") + std::strerror(errno));
  std::vector<unsigned char> h;
  h.insert(h.end(), std::begin(kRecordingMagic), std::end(kRecordingMagic));
  put(h, kRecordingVersion);
  put(h, header.instruments);
  put(h, header.haptic_rate_hz);
  put(h, header.timestep);
  put(h, header.mode);
  put_string(h, header.kernel_path);
  put_string(h, header.scene_path);
  put_string(h, header.scene_text);
  if (::write(fd_, h.data(), h.size()) != static_cast<ssize_t>(h.size())) {
    ::close(fd_);
    throw FileError(file.string(), FileLocation::none(), "cannot write the header");
  }
  block_.reserve(kBlockRecords * std::max(sizeof(TickRecord), sizeof(StepRecord)));
  thread_ = std::thread([this] { run(); });
}

RecordingWriter::~RecordingWriter() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) ::close(fd_);
}

void RecordingWriter::run() {
  const auto period = std::chrono::duration<double>(kFlushPeriod / 5);
  while (!stop_.load(std::memory_order_acquire)) {
    drain();
    std::this_thread::sleep_for(period);
  }
}

void RecordingWriter::append_record(const void* record, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(record);
  block_.insert(block_.end(), p, p + bytes);
  if (++block_records_ == kBlockRecords) flush_block();
}

void RecordingWriter::flush_block() {
  if (block_records_ == 0) return;
  write_block(block_, block_records_);
  block_.clear();
  block_records_ = 0;
}

void RecordingWriter::write_block(const std::vector<unsigned char>& payload, std::uint32_t records) {
  BlockHeader bh{};
  std::memcpy(bh.magic, kBlockMagic, 4);
  bh.records = records;
  bh.payload_bytes = static_cast<std::uint32_t>(payload.size());
  bh.checksum = fnv1a(payload.data(), payload.size());
  // One writev per block: a killed process leaves whole blocks (the kernel has them) and at
  // most one partial block at the end, which the reader reports. No allocation.
  iovec parts[2] = {{&bh, sizeof(bh)}, {const_cast<unsigned char*>(payload.data()), payload.size()}};
  std::size_t total = sizeof(bh) + payload.size();
  int first = 0;
  while (total > 0) {
    const ssize_t n = ::writev(fd_, parts + first, 2 - first);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (error_.empty()) error_ = std::string("write failed: ") + std::strerror(errno);
      return;
    }
    auto done = static_cast<std::size_t>(n);
    total -= done;
    while (first < 2 && done >= parts[first].iov_len) done -= parts[first++].iov_len;
    if (first < 2) {
      parts[first].iov_base = static_cast<unsigned char*>(parts[first].iov_base) + done;
      parts[first].iov_len -= done;
    }
  }
}

void RecordingWriter::drain() {
  TickRecord t;
  StepRecord s;
  bool any = true;
  while (any) {
    any = false;
    if (steps_.pop(s)) {
      append_record(&s, sizeof(s));
      ++steps_written_;
      any = true;
    }
    if (ticks_.pop(t)) {
      append_record(&t, sizeof(t));
      ++ticks_written_;
      any = true;
    }
  }
  flush_block();
}

void RecordingWriter::finish(EndRecord end) {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  drain();
  end.steps = steps_written_;
  end.ticks = ticks_written_;
  end.dropped = dropped();
  append_record(&end, sizeof(end));
  flush_block();
  if (fd_ >= 0 && ::close(fd_) != 0 && error_.empty()) error_ = std::string("close failed: ") + std::strerror(errno);
  fd_ = -1;
  if (!error_.empty()) throw FileError(file_.string(), FileLocation::none(), error_);
}

namespace {

class Cursor {
 public:
  Cursor(const std::string& file, std::string_view data) : file_(file), data_(data) {}
  std::size_t offset() const { return offset_; }
  std::size_t left() const { return data_.size() - offset_; }
  const unsigned char* here() const { return reinterpret_cast<const unsigned char*>(data_.data()) + offset_; }
  template <typename T>
  T take(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, here(), sizeof(T));
    offset_ += sizeof(T);
    return v;
  }
  std::string take_string(const char* what) {
    const auto n = take<std::uint64_t>(what);
    need(n, what);
    std::string s(data_.substr(offset_, n));
    offset_ += n;
    return s;
  }
  void skip(std::size_t n) { offset_ += n; }
  void need(std::uint64_t n, const char* what) const {
    if (n > left())
      throw FileError(file_, FileLocation::byte(offset_), std::string("truncated: ") + what + " needs " +
                                                              std::to_string(n) + " bytes, " +
                                                              std::to_string(left()) + " left");
  }

 private:
  const std::string& file_;
  std::string_view data_;
  std::size_t offset_ = 0;
};

bool finite(const PoseWords& w) {
  return std::all_of(w.begin(), w.end(), [](double x) { return std::isfinite(x); });
}

// A rotation the simulation can take as it is (from_words does not normalise); the tolerance is
// far above rounding and far below any garbage.
bool unit_rotation(const PoseWords& w) {
  const double n2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3];
  return std::abs(n2 - 1) <= 1e-3;
}

// What replay and the replay device feed back into a simulation; empty when fine.
std::string check_tick(const TickRecord& r, std::uint32_t instruments) {
  if (r.instruments > instruments)
    return "tick " + std::to_string(r.tick) + " has " + std::to_string(r.instruments) + " instruments, the header " +
           std::to_string(instruments);
  for (std::uint32_t i = 0; i < r.instruments; ++i) {
    const TickInstrument& t = r.instrument[i];
    if (t.status > static_cast<std::uint32_t>(DeviceStatus::kDisconnected))
      return "tick " + std::to_string(r.tick) + ": unknown device status " + std::to_string(t.status);
    if (!finite(t.device_pose) || !finite(t.proxy_pose) || !std::isfinite(t.jaw))
      return "tick " + std::to_string(r.tick) + ": non-finite pose or jaw";
  }
  return {};
}

std::string check_step(const StepRecord& r, std::uint32_t instruments) {
  const std::string step = "step " + std::to_string(r.step);
  if (!std::isfinite(r.dt) || !(r.dt > 0)) return step + ": dt must be finite and > 0";
  if (r.instruments > instruments)
    return step + " has " + std::to_string(r.instruments) + " instruments, the header " + std::to_string(instruments);
  for (std::uint32_t i = 0; i < r.instruments; ++i) {
    const StepInstrument& s = r.instrument[i];
    if (s.mode > 2) return step + ": unknown instrument mode " + std::to_string(s.mode);
    if (s.mode == 0) continue;  // keyframes: the pose is not read
    if (!finite(s.pose) || !std::isfinite(s.jaw)) return step + ": non-finite pose or jaw";
    if (!unit_rotation(s.pose)) return step + ": the rotation is not a unit quaternion";
  }
  return {};
}

// Parses one block's payload into the recording; returns an error text (empty when good) and
// then leaves `rec`'s records as they were.
std::string parse_payload(const unsigned char* p, std::size_t n, std::uint32_t records, Recording& rec,
                          std::size_t& bad_at) {
  const std::size_t ticks = rec.ticks.size(), steps = rec.steps.size();
  const bool had_end = rec.end.has_value();
  const auto fail = [&](std::string why) {
    rec.ticks.resize(ticks);
    rec.steps.resize(steps);
    if (!had_end) rec.end.reset();
    return why;
  };
  std::size_t at = 0;
  for (std::uint32_t i = 0; i < records; ++i) {
    bad_at = at;
    if (n - at < 8) return fail("record header past the block's end");
    std::uint32_t type = 0, bytes = 0;
    std::memcpy(&type, p + at, 4);
    std::memcpy(&bytes, p + at + 4, 4);
    if (bytes > n - at) return fail("record of " + std::to_string(bytes) + " bytes past the block's end");
    if (rec.end) return fail("record after the end record");
    if (type == static_cast<std::uint32_t>(RecordType::kTick) && bytes == sizeof(TickRecord)) {
      TickRecord r;
      std::memcpy(&r, p + at, sizeof r);
      if (std::string why = check_tick(r, rec.header.instruments); !why.empty()) return fail(why);
      rec.ticks.push_back(r);
    } else if (type == static_cast<std::uint32_t>(RecordType::kStep) && bytes == sizeof(StepRecord)) {
      StepRecord r;
      std::memcpy(&r, p + at, sizeof r);
      if (std::string why = check_step(r, rec.header.instruments); !why.empty()) return fail(why);
      rec.steps.push_back(r);
    } else if (type == static_cast<std::uint32_t>(RecordType::kEnd) && bytes == sizeof(EndRecord)) {
      EndRecord r;
      std::memcpy(&r, p + at, sizeof r);
      rec.end = r;
    } else {
      return fail("unknown record (type " + std::to_string(type) + ", " + std::to_string(bytes) + " bytes)");
    }
    at += bytes;
  }
  bad_at = at;
  if (at != n) return fail("block holds " + std::to_string(n - at) + " bytes beyond its records");
  return {};
}

// A kernel path as cpu_features names them: a short lowercase word.
bool kernel_path_name_ok(const std::string& s) {
  return !s.empty() && s.size() <= 32 && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-';
  });
}

void read_header(Cursor& c, const std::string& file, std::string_view data, RecordingHeader& h) {
  c.need(sizeof kRecordingMagic, "the magic");
  if (std::memcmp(data.data(), kRecordingMagic, sizeof kRecordingMagic) != 0)
    throw FileError(file, FileLocation::byte(0), "not a trocar recording (no TROCREC1 magic)");
  c.take<std::array<char, 8>>("the magic");
  const auto field_error = [&](std::size_t at, const std::string& why) {
    return FileError(file, FileLocation::byte(at), why);
  };
  std::size_t at = c.offset();
  h.version = c.take<std::uint32_t>("the version");
  if (h.version < kRecordingOldestVersion || h.version > kRecordingVersion)
    throw field_error(at, "version " + std::to_string(h.version) + " (this build reads " +
                              std::to_string(kRecordingOldestVersion) + " to " + std::to_string(kRecordingVersion) + ")");
  at = c.offset();
  h.instruments = c.take<std::uint32_t>("the instrument count");
  if (h.instruments > kMaxRuntimeInstruments)
    throw field_error(at, "instrument count " + std::to_string(h.instruments) + " above " +
                              std::to_string(kMaxRuntimeInstruments));
  at = c.offset();
  h.haptic_rate_hz = c.take<double>("the haptic rate");
  if (!std::isfinite(h.haptic_rate_hz) || !(h.haptic_rate_hz > 0)) throw field_error(at, "haptic rate must be finite and > 0");
  at = c.offset();
  h.timestep = c.take<double>("the timestep");
  if (!std::isfinite(h.timestep) || !(h.timestep > 0)) throw field_error(at, "timestep must be finite and > 0");
  at = c.offset();
  h.mode = c.take<std::uint32_t>("the mode");
  if (h.mode > 1) throw field_error(at, "mode " + std::to_string(h.mode) + " (0 multirate, 1 lock-step)");
  if (h.version >= 2) {
    at = c.offset();
    h.kernel_path = c.take_string("the kernel path");
    if (!kernel_path_name_ok(h.kernel_path)) throw field_error(at, "the kernel path is not a name");
  } else {
    h.kernel_path = kUnknownKernelPath;
  }
  h.scene_path = c.take_string("the scene path");
  h.scene_text = c.take_string("the scene text");
}

}  // namespace

std::uint64_t block_checksum(const unsigned char* payload, std::size_t bytes, std::uint32_t version) {
  return fnv1a(payload, bytes, version == 1 ? kVersion1Basis : kFnvBasis);
}

Recording parse_recording(std::string_view data, const std::string& file, bool strict) {
  Recording rec;
  rec.file_bytes = data.size();
  Cursor c(file, data);
  read_header(c, file, data, rec.header);
  rec.complete_bytes = c.offset();

  while (c.left() > 0) {
    const std::size_t block_at = c.offset();
    try {
      const auto bh = c.take<BlockHeader>("a block header");
      if (std::memcmp(bh.magic, kBlockMagic, 4) != 0) throw FileError(file, FileLocation::byte(block_at), "no block magic TRBK");
      c.need(bh.payload_bytes, "a block's payload");
      const unsigned char* payload = c.here();
      if (block_checksum(payload, bh.payload_bytes, rec.header.version) != bh.checksum)
        throw FileError(file, FileLocation::byte(block_at), "block checksum mismatch (corrupt data)");
      std::size_t bad_at = 0;
      const std::string why = parse_payload(payload, bh.payload_bytes, bh.records, rec, bad_at);
      if (!why.empty()) throw FileError(file, FileLocation::byte(c.offset() + bad_at), why);
      c.skip(bh.payload_bytes);
      rec.complete_bytes = c.offset();
    } catch (const FileError&) {
      if (strict) throw;
      return rec;
    }
  }
  if (strict && !rec.end)
    throw FileError(file, FileLocation::byte(rec.complete_bytes), "truncated: no end record (the session did not finish)");
  return rec;
}

Recording read_recording(const std::filesystem::path& path, bool strict) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(file, FileLocation::none(), "cannot open");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_recording(data, file, strict);
}

}  // namespace trocar
