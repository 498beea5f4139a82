// exact8_avx512: the narrow phase's exact test on eight pairs at once (narrow_phase_exact.h)
// with AVX-512, compiled with -ffp-contract=off (CMakeLists.txt): AVX-512 brings FMA, and GCC
// would otherwise fuse a * b + c, which rounds differently from the scalar code.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/geometry/tolerance.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "trocar/collision/target_region.h"

// Everything below, and only that (the library headers are in above), is compiled for
// AVX-512 (target_region.h).
TROCAR_TARGET_REGION_BEGIN("avx512f,avx512vl,avx512dq")
// GCC 12's AVX-512 headers pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins of _mm512_insertf64x4 and friends, which -Wuninitialized reports once inlined here.
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)  // a GCC-only warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "trocar/collision/narrow_phase_exact.h"
#include "trocar/collision/narrow_phase_lanes_avx512.h"

namespace trocar::narrow_detail {
int exact8_avx512(const Vec3* const (&c)[8][6], TriTriResult (&r)[8]) {
  return static_cast<int>(Exact<Lanes8>::run(c, r));
}

}  // namespace trocar::narrow_detail
TROCAR_TARGET_REGION_END()

#else

namespace trocar::narrow_detail {
int exact8_avx512(const Vec3* const (&)[8][6], TriTriResult (&)[8]) { std::abort(); }
}  // namespace trocar::narrow_detail

#endif
