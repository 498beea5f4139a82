#pragma once
/// Swept (continuous) reference check between an instrument and a tissue over one step's linear
/// motion: how many feature crossings did a discrete test at the two frames miss? A measuring
/// instrument for the response study, not part of Simulation::step.
#include <cstdint>
#include <span>

#include "trocar/core/types.h"

namespace trocar {

/// Relative contact tolerance of the swept test: at a coplanarity time the features touch when
/// their distance is at most kSweptTolerance × the largest side of the four points' box
/// (dimensionless; loose enough for the bisected root, far below any feature size).
inline constexpr Real kSweptTolerance = 1e-7;

/// One object at the start and the end of a step (same triangles, same vertex count).
struct SweptObject {
  std::span<const Vec3> positions_start;  ///< world positions at the earlier frame (metres)
  std::span<const Vec3> positions_end;    ///< world positions at the later frame (metres)
  std::span<const Triangle> triangles;    ///< vertex index triplets
};

/// Result of swept_check(). An event is one feature pair (a vertex and a triangle, or two
/// edges, one feature from each object) that becomes coplanar and touching at some time in
/// [0, 1] of the linear motion; counted once per feature pair however many times it touches.
struct SweptCheckResult {
  std::uint64_t vertex_triangle_events = 0;  ///< vertex of either object through a triangle of the other
  std::uint64_t edge_edge_events = 0;        ///< instrument edge across a tissue edge
  /// Events a discrete detector running at the two frames never sees: at neither frame does it
  /// report a contact on a tissue triangle incident to a vertex of the tissue's feature (the
  /// tissue triangle, the tissue vertex or the tissue edge of the event). The instrument side is
  /// not required to match: a tool tip pressed deeper than its first ring of triangles touches
  /// the tissue only through triangles not incident to the tip, and the detector has still seen
  /// the penetration there.
  std::uint64_t missed_vertex_triangle = 0;
  std::uint64_t missed_edge_edge = 0;        ///< the same for edge–edge events
  std::uint64_t triangle_pairs_tested = 0;   ///< triangle pairs whose swept boxes overlap
  /// All missed events.
  std::uint64_t missed() const { return missed_vertex_triangle + missed_edge_edge; }
  /// All events.
  std::uint64_t events() const { return vertex_triangle_events + edge_edge_events; }
};

/// Vertex–triangle and edge–edge continuous tests (Provot 1997; Bridson, Fedkiw and Anderson
/// 2002): with every vertex moving linearly from start to end, the coplanarity times of four
/// points are the roots in [0, 1] of a cubic; at each root the features are tested for contact
/// (point in triangle, or segments meeting) within kSweptTolerance of the four points' extent.
/// Candidates come from an AABB tree over the tissue's swept triangle boxes queried with each
/// instrument triangle's swept box; features shared by several triangle pairs are counted once.
/// The discrete contacts at the two frames come from a CollisionDetector (OHC).
/// Allocates (it is a measuring tool). Throws trocar::Error when start and end vertex counts
/// differ.
SweptCheckResult swept_check(const SweptObject& instrument, const SweptObject& tissue);

/// Roots of the coplanarity cubic of points x0..x3 moving linearly with velocities v0..v3 over
/// t ∈ [0, 1]: times t with (x1(t)−x0(t)) × (x2(t)−x0(t)) · (x3(t)−x0(t)) = 0. Writes up to 3
/// roots, ascending, into `roots` and returns how many. Exposed for tests.
int coplanarity_times(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, const Vec3& v0,
                      const Vec3& v1, const Vec3& v2, const Vec3& v3, Real roots[3]);

}  // namespace trocar
