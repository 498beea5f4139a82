// libFuzzer target for the OpenIGTLink stream parser (src/trocar/device/openigtlink_parser.h):
// the input is a client's byte stream. Every pose must be finite, in metres below the float32
// range, with a unit rotation; and the parser must make the same of the stream however it is
// cut (whole, then in pieces whose sizes come from the input's first byte). Any difference,
// crash, hang or sanitizer report is a finding.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trocar/device/openigtlink_parser.h"

namespace {

struct Event {
  bool pose;
  trocar::Pose value;
};

struct Recorder final : trocar::IgtlStreamParser::Sink {
  std::vector<Event> events;
  void pose(const trocar::Pose& p) override {
    if (!p.translation.allFinite() || p.translation.cwiseAbs().maxCoeff() > 3.5e35) __builtin_trap();
    if (!p.rotation.coeffs().allFinite() || std::abs(p.rotation.norm() - 1) > 1e-9) __builtin_trap();
    events.push_back({true, p});
  }
  void malformed() override { events.push_back({false, {}}); }
};

// Feeds the stream in pieces of 1, 2, …, `step`, 1, 2, … bytes (step 0: whole), then ends it.
std::vector<Event> parse(const std::uint8_t* data, std::size_t size, std::size_t step) {
  trocar::IgtlStreamParser parser;
  Recorder r;
  std::size_t cut = 1;
  for (std::size_t at = 0; at < size;) {
    const std::size_t n = step == 0 ? size : std::min(cut, size - at);
    if (!parser.feed(data + at, n, r)) break;  // garbage: the driver closes the connection here
    at += n;
    if (step > 0) cut = cut % step + 1;
  }
  parser.finish(r);
  return r.events;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t step = data[0] % 64 + 1;
  const std::vector<Event> whole = parse(data + 1, size - 1, 0);
  const std::vector<Event> pieces = parse(data + 1, size - 1, step);
  if (whole.size() != pieces.size()) __builtin_trap();
  for (std::size_t i = 0; i < whole.size(); ++i) {
    if (whole[i].pose != pieces[i].pose) __builtin_trap();
    if (whole[i].pose && !(whole[i].value.translation == pieces[i].value.translation &&
                           whole[i].value.rotation.coeffs() == pieces[i].value.rotation.coeffs()))
      __builtin_trap();
  }
  return 0;
}
