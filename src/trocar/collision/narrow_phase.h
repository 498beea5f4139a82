#pragma once
/// Narrow phase: the exact triangle–triangle test on every candidate pair.
#include <span>
#include <vector>

#include "trocar/collision/broad_phase.h"
#include "trocar/collision/contact.h"

namespace trocar {

/// Replaces `out` with one Contact per candidate pair whose triangles intersect
/// (intersect_triangles, touching counts), with its kind and intersection segment, sorted by
/// (object_a, object_b, triangle_a, triangle_b). Triangle a's corners are the first three
/// arguments of the test, so the segment does not depend on the broad phase. Allocates only
/// when `out` needs more capacity than it has. `allow_simd` = false forces the portable
/// rejection tests (the AVX2 ones run only where the CPU has AVX2 and FMA and the environment
/// has no TROCAR_SIMD=off); the contacts are the same either way.
void narrow_phase(std::span<const CollisionObject> objects, std::span<const CandidatePair> pairs,
                  std::vector<Contact>& out, bool allow_simd = true);

}  // namespace trocar
