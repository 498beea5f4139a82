// libFuzzer target for the session recording reader (runtime/recording.h): any input must either
// read or throw trocar::FileError, strictly and leniently, and what reads must hold what a replay
// relies on. Each input is read twice: as it is (the checksums almost always fail, which tests
// the block walk and the header), and with every block's checksum made right, so that the
// fuzzer reaches the records themselves.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include "trocar/core/error.h"
#include "trocar/runtime/recording.h"

namespace {

using trocar::Recording;

void check(bool ok) {
  if (!ok) __builtin_trap();
}

bool finite(const trocar::PoseWords& w) {
  for (double x : w)
    if (!std::isfinite(x)) return false;
  return true;
}

// What every recording that reads promises.
void check_recording(const Recording& r, std::size_t size) {
  check(r.file_bytes == size && r.complete_bytes <= r.file_bytes);
  check(r.header.instruments <= trocar::kMaxRuntimeInstruments);
  check(std::isfinite(r.header.haptic_rate_hz) && r.header.haptic_rate_hz > 0);
  check(std::isfinite(r.header.timestep) && r.header.timestep > 0 && r.header.mode <= 1);
  check(!r.header.kernel_path.empty());
  for (const trocar::TickRecord& t : r.ticks) {
    check(t.instruments <= r.header.instruments);
    for (std::uint32_t i = 0; i < t.instruments; ++i)
      check(finite(t.instrument[i].device_pose) && std::isfinite(t.instrument[i].jaw));
  }
  for (const trocar::StepRecord& s : r.steps) {
    check(std::isfinite(s.dt) && s.dt > 0 && s.instruments <= r.header.instruments);
    for (std::uint32_t i = 0; i < s.instruments; ++i) {
      check(s.instrument[i].mode <= 2);
      if (s.instrument[i].mode != 0) check(finite(s.instrument[i].pose) && std::isfinite(s.instrument[i].jaw));
    }
  }
}

std::optional<Recording> read(const std::string& bytes, bool strict) {
  try {
    return trocar::parse_recording(bytes, "fuzz.trec", strict);
  } catch (const trocar::FileError&) {
    return std::nullopt;  // malformed input, reported properly
  }
}

void read_both_ways(const std::string& bytes) {
  const std::optional<Recording> strict = read(bytes, true);
  const std::optional<Recording> lenient = read(bytes, false);
  if (strict) {  // a strict read is whole, and the lenient read agrees with it
    check_recording(*strict, bytes.size());
    check(strict->end.has_value() && strict->complete_bytes == bytes.size());
    check(lenient && lenient->ticks.size() == strict->ticks.size() && lenient->steps.size() == strict->steps.size());
  }
  if (!lenient) return;  // only a bad header stops a lenient read
  check_recording(*lenient, bytes.size());
  // The complete blocks alone read to the same records.
  const std::optional<Recording> prefix = read(bytes.substr(0, lenient->complete_bytes), false);
  check(prefix && prefix->ticks.size() == lenient->ticks.size() && prefix->steps.size() == lenient->steps.size() &&
        prefix->end.has_value() == lenient->end.has_value());
}

// Rewrites every block's checksum to match its payload (the header layout of recording_format.h);
// false when the header does not get that far.
bool fix_checksums(std::string& bytes) {
  std::size_t at = 8;
  const auto take = [&](std::size_t n, void* out) {
    if (bytes.size() - at < n) return false;
    if (out != nullptr) std::memcpy(out, bytes.data() + at, n);
    at += n;
    return true;
  };
  const auto skip_string = [&] {
    std::uint64_t n = 0;
    if (!take(8, &n) || bytes.size() - at < n) return false;
    at += n;
    return true;
  };
  std::uint32_t version = 0;
  if (bytes.size() < at || !take(4, &version) || !take(4 + 8 + 8 + 4, nullptr)) return false;
  if (version >= 2 && !skip_string()) return false;
  if (!skip_string() || !skip_string()) return false;
  while (bytes.size() - at >= 24) {
    std::uint32_t payload = 0;
    std::memcpy(&payload, bytes.data() + at + 8, 4);
    if (bytes.size() - at - 24 < payload) break;
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at + 24);
    const std::uint64_t sum = trocar::block_checksum(p, payload, version);
    std::memcpy(bytes.data() + at + 16, &sum, 8);
    at += 24 + payload;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  read_both_ways(bytes);
  if (fix_checksums(bytes)) read_both_ways(bytes);
  return 0;
}
