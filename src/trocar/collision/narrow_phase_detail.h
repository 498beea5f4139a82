#pragma once
/// Internal to the narrow phase (narrow_phase.cpp, narrow_phase_avx2.cpp): the exact test of one
/// candidate, and the AVX2 rejection tests chosen at run time.
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/contact.h"

namespace trocar::narrow_detail {

/// The exact test (intersect_triangles, A's corners first); appends the contact when the
/// triangles intersect.
void exact_candidate(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair& pair,
                     std::vector<Contact>& out);

/// The rejection tests for four candidates of the same object pair at once (AVX2 + FMA), then
/// exact_candidate() on those they keep. Requires cpu_has_avx2_fma().
void reject4_avx2(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs,
                  std::vector<Contact>& out);

}  // namespace trocar::narrow_detail
