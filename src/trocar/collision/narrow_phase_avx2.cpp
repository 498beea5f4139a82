// The narrow phase's rejection tests for four candidates at once (AVX2 + FMA, chosen at run
// time): narrow_phase_reject.h with four lanes of __m256d and vector masks.
#include <cstdlib>
#include <limits>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "trocar/collision/target_region.h"

// Everything below, and only that (the library headers are in above), is compiled for
// AVX2 and FMA (target_region.h).
TROCAR_TARGET_REGION_BEGIN("avx2,fma")
#include "trocar/collision/narrow_phase_lanes_avx2.h"
#include "trocar/collision/narrow_phase_reject.h"

namespace trocar::narrow_detail {
int reject4_avx2(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs) {
  return static_cast<int>(Reject<Lanes4>::run(oa, ob, pairs));
}

}  // namespace trocar::narrow_detail
TROCAR_TARGET_REGION_END()

#else

namespace trocar::narrow_detail {
int reject4_avx2(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx2_fma() is false
}
}  // namespace trocar::narrow_detail

#endif
