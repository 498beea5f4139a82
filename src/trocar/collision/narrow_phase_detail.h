#pragma once
/// Internal to the narrow phase (narrow_phase.cpp, narrow_phase_avx2.cpp): the exact test of one
/// candidate, and the AVX2 rejection tests chosen at run time.
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/contact.h"
#include "trocar/geometry/triangle_triangle.h"

namespace trocar::narrow_detail {

/// The exact test (intersect_triangles, A's corners first); appends the contact when the
/// triangles intersect.
void exact_candidate(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair& pair,
                     std::vector<Contact>& out);

/// Appends the contact of a candidate whose exact test gave r, when r intersects.
void append_contact(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair& pair,
                    const TriTriResult& r, std::vector<Contact>& out);

/// The rejection tests for four candidates of the same object pair at once (AVX2 + FMA); returns
/// the mask (bit k: candidate k) of those no test rejects. Requires cpu_has_avx2_fma().
int reject4_avx2(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair* pairs);

/// intersect_triangles on four pairs at once (c[k]: a0, a1, a2, b0, b1, b2 of pair k), bit for
/// bit, for the common case (two proper triangles crossing at an angle, no vertex within the
/// tolerance of the other plane); returns the mask of the lanes it answered in r, the others are
/// left to intersect_triangles. Requires cpu_has_avx2().
int exact4_avx2(const Vec3* const (&c)[4][6], TriTriResult (&r)[4]);

}  // namespace trocar::narrow_detail
