// exact4_avx2: the narrow phase's exact test on four pairs at once (narrow_phase_exact.h) with
// AVX2, compiled without FMA (a target of AVX2 alone, and -ffp-contract=off from CMakeLists.txt):
// GCC's intrinsics are plain vector arithmetic, which it would otherwise fuse into a * b + c.
#include <cstdlib>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/geometry/tolerance.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "trocar/collision/target_region.h"

// Everything below, and only that (the library headers are in above), is compiled for
// AVX2 (target_region.h).
TROCAR_TARGET_REGION_BEGIN("avx2")
#include "trocar/collision/narrow_phase_exact.h"
#include "trocar/collision/narrow_phase_lanes_avx2.h"

namespace trocar::narrow_detail {
int exact4_avx2(const Vec3* const (&c)[4][6], TriTriResult (&r)[4]) {
  return static_cast<int>(Exact<Lanes4>::run(c, r));
}

}  // namespace trocar::narrow_detail
TROCAR_TARGET_REGION_END()

#else

namespace trocar::narrow_detail {
int exact4_avx2(const Vec3* const (&)[4][6], TriTriResult (&)[4]) { return 0; }
}  // namespace trocar::narrow_detail

#endif
