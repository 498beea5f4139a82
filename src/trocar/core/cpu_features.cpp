#include "trocar/core/cpu_features.h"

#include <cstdlib>
#include <string_view>

namespace trocar {
namespace {

bool simd_allowed() {
  const char* env = std::getenv("TROCAR_SIMD");
  return !(env != nullptr && std::string_view(env) == "off");
}

}  // namespace

bool cpu_has_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = __builtin_cpu_supports("avx2") && simd_allowed();
  return has;
#else
  return false;
#endif
}

bool cpu_has_avx2_fma() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = cpu_has_avx2() && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

bool cpu_has_avx512() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = cpu_has_avx2_fma() && __builtin_cpu_supports("avx512f") &&
                          __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
  return has;
#else
  return false;
#endif
}

}  // namespace trocar
