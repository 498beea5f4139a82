// libFuzzer target for read_ply: any input must either give a valid mesh or throw FileError
// (fuzz_common.h); any other exception, crash, hang or sanitizer report is a finding.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return trocar::fuzz::run_reader(data, size, trocar::read_ply, "fuzz.ply");
}
