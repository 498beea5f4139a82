// The narrow phase's rejection tests for eight candidates at once (AVX-512, chosen at run time):
// narrow_phase_reject.h with eight lanes of __m512d and mask registers, the same tests in the
// same order with the same margins as the four-lane AVX2 version. Eight lanes halve the
// arithmetic per candidate, and 32 registers hold what the four-lane version spills.
#include <cstdlib>
#include <limits>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "trocar/collision/target_region.h"

// Everything below, and only that (the library headers are in above), is compiled for
// AVX-512 (with AVX2 and FMA) (target_region.h).
TROCAR_TARGET_REGION_BEGIN("avx512f,avx512vl,avx512dq,avx2,fma")
// GCC 12's own AVX-512 headers pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins of _mm512_insertf64x4 and friends, which -Wuninitialized reports once inlined here.
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)  // a GCC-only warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "trocar/collision/narrow_phase_lanes_avx512.h"
#include "trocar/collision/narrow_phase_reject.h"

namespace trocar::narrow_detail {
int reject8_avx512(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs) {
  return static_cast<int>(Reject<Lanes8>::run(oa, ob, pairs));
}

}  // namespace trocar::narrow_detail
TROCAR_TARGET_REGION_END()

#else

namespace trocar::narrow_detail {
int reject8_avx512(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx512() is false
}
}  // namespace trocar::narrow_detail

#endif
