#include "trocar/core/cpu_features.h"

#include <atomic>
#include <cstdlib>
#include <string_view>

namespace trocar {
namespace {

bool simd_allowed() {
  const char* env = std::getenv("TROCAR_SIMD");
  return !(env != nullptr && std::string_view(env) == "off");
}

// What the CPU and the environment allow, checked once.
KernelPath native_path() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const KernelPath path = [] {
    if (!simd_allowed() || !__builtin_cpu_supports("avx2")) return KernelPath::kPortable;
    if (!__builtin_cpu_supports("fma")) return KernelPath::kAvx2NoFma;
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512dq"))
      return KernelPath::kAvx512;
    return KernelPath::kAvx2;
  }();
  return path;
#else
  return KernelPath::kPortable;
#endif
}

std::atomic<KernelPath> cap{KernelPath::kAvx512};

}  // namespace

KernelPath kernel_path() {
  const KernelPath native = native_path();
  const KernelPath widest = cap.load(std::memory_order_relaxed);
  return widest < native ? widest : native;
}

const char* kernel_path_name(KernelPath path) {
  switch (path) {
    case KernelPath::kPortable: return "portable";
    case KernelPath::kAvx2NoFma: return "avx2-nofma";
    case KernelPath::kAvx2: return "avx2";
    case KernelPath::kAvx512: return "avx512";
  }
  return "portable";
}

void cap_kernel_path(KernelPath widest) { cap.store(widest, std::memory_order_relaxed); }

bool cpu_has_avx2() { return kernel_path() >= KernelPath::kAvx2NoFma; }

bool cpu_has_avx2_fma() { return kernel_path() >= KernelPath::kAvx2; }

bool cpu_has_avx512() { return kernel_path() >= KernelPath::kAvx512; }

}  // namespace trocar
