// The narrow phase's rejection tests for four candidates at once (AVX2 + FMA, chosen at run
// time): narrow_phase_reject.h with four lanes of __m256d and vector masks.
#include <cstdlib>
#include <limits>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/narrow_phase_detail.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

// Everything below (and only that: the library headers are in above) is compiled for AVX2 and
// FMA. GCC takes the target for the region by pragma; clang ignores that pragma and takes an
// attribute applied to every function defined in the region instead.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
#include "trocar/collision/narrow_phase_lanes_avx2.h"
#include "trocar/collision/narrow_phase_reject.h"

namespace trocar::narrow_detail {
int reject4_avx2(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs) {
  return static_cast<int>(Reject<Lanes4>::run(oa, ob, pairs));
}

}  // namespace trocar::narrow_detail
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

#else

namespace trocar::narrow_detail {
int reject4_avx2(const CollisionObject&, const CollisionObject&, const CandidatePair*) {
  std::abort();  // never called: cpu_has_avx2_fma() is false
}
}  // namespace trocar::narrow_detail

#endif
