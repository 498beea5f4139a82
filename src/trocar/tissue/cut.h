#pragma once
/// Topology change of a mass-spring tissue: triangles opened by an electrosurgical cut
/// (docs/electrosurgery.md). The cut model is a new MassSpringSettings derived from the old one
/// (never rebuilt from a material: the tissue keeps its own rest state, springs and masses).
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/tissue/settings.h"

namespace trocar {

/// A tissue's model after some of its triangles opened (docs/electrosurgery.md).
struct CutTopology {
  MassSpringSettings settings;                 ///< the cut model
  std::vector<std::uint32_t> vertex_origin;    ///< per new vertex: the old vertex it copies
  std::vector<std::uint32_t> triangle_origin;  ///< per new triangle: the old triangle
  std::vector<std::uint32_t> spring_origin;    ///< per new spring: the old spring it copies
};

/// Removes the `removed` triangles (old indices, any order; duplicates and out-of-range indices
/// ignored) from `settings` and returns the cut model, in O(T + S) (flat arrays, one hash table of
/// the old springs, sorts only within one vertex's triangles). Rules:
/// 1. Kept triangles keep their order (triangle_origin increases) and their rest areas.
///    mean_rest_area is kept: it normalises k_area, and the material did not change.
/// 2. A vertex no kept triangle uses is dropped; the others keep their order (compacted).
/// 3. A vertex of a removed triangle whose kept triangles form more than one fan (triangles
///    around it joined through edges that contain it and that two or more kept triangles share)
///    is split, one copy per fan, so the surface stays vertex-manifold (no bow-tie, and two pieces
///    a cut separates are not held together by one vertex). The fan with the lowest kept triangle
///    keeps the vertex's place; the other copies follow all kept vertices, ordered by (old vertex,
///    fan's lowest triangle). Vertices of no removed triangle are never split (not even a bow-tie
///    of the input): a cut changes only what it touches.
/// 4. rest_positions, home_positions and fixed follow vertex_origin. A vertex of no removed
///    triangle keeps its mass bit for bit; one of a removed triangle gets m_old × (Σ area/3 of its
///    fan's kept triangles) / (Σ area/3 of all the old vertex's triangles), each corner counted as
///    build() counts it: the removed tissue's share leaves with it (it is vaporised), so with
///    masses lumped by area the total drops by exactly the removed triangles' mass. Degenerate
///    cases keep every mass > 0 and finite: an old vertex with no area at all splits its mass
///    equally among its fans; a fan of zero-area triangles beside others with area gets
///    1e-6 × m_old (build()'s share for a vertex without area), not conserved. inverse_masses =
///    1/m, 0 where fixed, as build() does.
/// 5. Springs are rebuilt in build()'s order from the new triangles: one structural spring per
///    unique edge (sorted vertex pairs, increasing), then one bending spring per edge that exactly
///    two distinct triangles share, between its two opposite vertices (skipped when they are the
///    same vertex). Each copies rest length, stiffness and damping from the old spring of the same
///    kind between the origin vertices (the first one, when the old model had several); a new
///    spring whose old one does not exist (a bending spring across a formerly non-manifold edge,
///    or k_bending = 0) is not created, so a cut never invents material.
/// 6. closed stays true only when nothing was removed: an open surface has no volume term.
///    rest_volume is kept (it is unused while closed is false).
/// 7. Every other field (k_area, k_volume, k_home, home_yield, damping, gravity) is copied.
/// 8. Never throws for a model build() (or this function) made. Nothing removed (empty span,
///    only duplicates of nothing, only out-of-range indices): the input is returned unchanged,
///    with identity maps, even if it has vertices no triangle uses. Everything removed: an empty
///    model (no vertices, triangles or springs; the scalar fields as above), which a caller
///    should treat as "the tissue is gone", not step; removing from it again returns it.
CutTopology remove_triangles(const MassSpringSettings& settings, std::span<const std::uint32_t> removed);

}  // namespace trocar
