#pragma once
/// Mesh repair: each step optional, run in the order of the RepairOptions fields.
#include <cstddef>
#include <string>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Which repair steps run, and their tolerances. Steps run in this order:
/// invalid triangles → merge → degenerate → duplicates → small components → winding →
/// outward orientation → unused vertices.
struct RepairOptions {
  /// Drop triangles with an out-of-range index or a corner at a non-finite position.
  bool drop_invalid_triangles = true;
  /// Merge vertices closer than the tolerance (see merge_tolerance_*). Tie rule: every vertex
  /// maps to the lowest-index vertex within the tolerance that is itself kept; vertex order
  /// is unchanged (merged vertices become unused and go in the unused-vertex step).
  bool merge_vertices = true;
  /// Absolute merge tolerance (file units). The tolerance used is
  /// max(merge_tolerance_abs, merge_tolerance_rel · bbox diagonal); 0 = exact equality.
  Real merge_tolerance_abs = 0;
  /// Merge tolerance relative to the bounding-box diagonal.
  Real merge_tolerance_rel = 0;
  /// Drop triangles with a repeated index or area < (degenerate_area_rel · diagonal)².
  bool drop_degenerate = true;
  /// Threshold for drop_degenerate (as validate()).
  Real degenerate_area_rel = 1e-7;
  /// Drop later copies of a triangle with the same vertex set (any order).
  bool drop_duplicate_triangles = true;
  /// Drop vertex-connected components with fewer triangles than this (0 = keep all).
  std::size_t min_component_triangles = 0;
  /// Drop components whose area is below this fraction of the total (0 = keep all).
  Real min_component_area_fraction = 0;
  /// Flip triangles so each edge-connected patch is consistently wound (BFS over edges with
  /// exactly two triangles; non-manifold edges do not propagate). The first triangle of each
  /// patch keeps its winding.
  bool make_winding_consistent = true;
  /// Flip every closed patch (all its edges shared by exactly two triangles) with negative
  /// signed volume. Needs make_winding_consistent (patches are single triangles without it).
  /// A closed inner shell meant as a cavity is turned outward too: switch this off for those.
  bool orient_outward = true;
  /// Remove vertices no triangle uses, remapping indices (normals follow their vertices).
  bool drop_unused_vertices = true;
};

/// What repair() changed. Plain data for text output.
struct RepairReport {
  std::size_t vertices_before = 0;            ///< vertex count on entry
  std::size_t triangles_before = 0;           ///< triangle count on entry
  std::size_t vertices_after = 0;             ///< vertex count on exit
  std::size_t triangles_after = 0;            ///< triangle count on exit
  std::size_t invalid_triangles_removed = 0;  ///< out-of-range or non-finite corners
  Real merge_tolerance = 0;                   ///< absolute tolerance the merge used
  std::size_t vertices_merged = 0;            ///< vertices mapped onto another one
  std::size_t degenerate_removed = 0;         ///< degenerate triangles dropped
  std::size_t duplicate_triangles_removed = 0;///< duplicate triangles dropped
  std::size_t components_removed = 0;         ///< small components dropped
  std::size_t component_triangles_removed = 0;///< their triangles
  std::size_t triangles_flipped = 0;          ///< triangles whose winding changed (net, both steps)
  std::size_t patches = 0;                    ///< edge-connected patches seen by the winding step
  std::size_t patches_flipped_outward = 0;    ///< closed patches flipped to positive volume
  std::size_t unused_vertices_removed = 0;    ///< unused vertices dropped
  bool normals_dropped = false;    ///< normals cleared because their count was not V on entry
  bool texcoords_dropped = false;  ///< texcoords cleared because their count was not 3·T on entry

  /// True when the mesh was modified.
  bool changed() const;
  /// One line per step that did something ("merged 22 vertices (tolerance 0)"); empty when
  /// nothing changed.
  std::vector<std::string> summary() const;
};

/// Repairs `mesh` in place. Per-vertex normals follow their vertices (a merged vertex keeps
/// the representative's normal); per-corner texcoords follow their triangles and corners
/// (a flip swaps corners 1 and 2 and their texcoords). Normals are not negated on flips.
/// O(V log V + T log T) (the merge is a spatial hash, expected O(V)).
RepairReport repair(TriMesh& mesh, const RepairOptions& options = {});

/// For each vertex, the lowest-index vertex within `tolerance` (itself when none): greedy in
/// index order, so representatives map to themselves. tolerance 0 = equal x, y, z (==, so
/// −0 == +0). Non-finite positions map to themselves. Shared by validate() and repair().
std::vector<std::uint32_t> vertex_representatives(const std::vector<Vec3>& positions, Real tolerance);

}  // namespace trocar
