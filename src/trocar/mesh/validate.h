#pragma once
/// Mesh validation: counts every defect the readers, repair() and the simulator care about.
/// The definitions follow the shared test meshes' SOURCES.md (see docs/mesh.md).
#include <cstddef>
#include <string>
#include <vector>

#include "trocar/core/aabb.h"
#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Which way a closed mesh's normals point.
enum class Orientation {
  kOutward,    ///< closed, consistently wound, signed volume > 0
  kInward,     ///< closed, consistently wound, signed volume < 0 (inside out)
  kUndefined,  ///< open, non-manifold edge, degenerate, inconsistently wound or zero volume
};

/// "outward", "inward" or "undefined".
const char* orientation_name(Orientation orientation);

/// Tolerances for validate().
struct ValidateOptions {
  /// Degenerate-triangle threshold: area < (degenerate_area_rel · bbox diagonal)².
  Real degenerate_area_rel = 1e-7;
  /// Near-duplicate vertices: distinct positions closer than near_duplicate_rel · bbox
  /// diagonal. 0 turns the (spatial hash) search off.
  Real near_duplicate_rel = 1e-6;
};

/// What validate() found. Plain data: every field is printable as text or JSON.
/// Triangles with an out-of-range index, or a corner at a non-finite position, are counted
/// and then left out of every other count (topology, area, volume, degeneracy).
struct MeshReport {
  std::size_t vertices = 0;              ///< vertex count (used or not)
  std::size_t triangles = 0;             ///< triangle count (all of them)
  std::size_t edges = 0;                 ///< unique undirected edges (valid triangles)
  std::size_t out_of_range_triangles = 0;///< triangles with an index ≥ vertices
  std::size_t nonfinite_vertices = 0;    ///< vertices with a NaN or infinite coordinate
  std::size_t nonfinite_triangles = 0;   ///< in-range triangles touching a non-finite vertex
  std::size_t boundary_edges = 0;        ///< edges used by exactly 1 triangle
  std::size_t nonmanifold_edges = 0;     ///< edges used by more than 2 triangles
  std::size_t nonmanifold_vertices = 0;  ///< vertices whose star is more than one fan
  std::size_t degenerate_triangles = 0;  ///< repeated index, or area < (1e-7·diagonal)²
  std::size_t duplicate_triangles = 0;   ///< extra copies of a vertex set (any order)
  std::size_t duplicate_vertices = 0;    ///< vertices equal (==) to an earlier one's x, y, z
  std::size_t near_duplicate_vertices = 0; ///< other vertices within near_duplicate_rel·diag of an earlier one
  std::size_t unused_vertices = 0;       ///< vertices no (valid) triangle references
  std::size_t inconsistent_edges = 0;    ///< interior edges both triangles traverse the same way
  std::size_t components = 0;            ///< vertex-connected components
  long long euler_characteristic = 0;    ///< V_used − E + T over valid triangles
  bool closed = false;    ///< ≥ 1 triangle, no boundary, no non-manifold edge, no degenerate
  bool manifold = false;  ///< no non-manifold edge and no non-manifold vertex
  Real signed_volume = 0; ///< Σ a·(b×c)/6 about the bbox centre (valid triangles)
  Orientation orientation = Orientation::kUndefined;  ///< from the volume when closed
  Real area = 0;          ///< total area (valid triangles)
  Aabb bounds;            ///< box of the finite positions
  Real near_duplicate_tolerance = 0;  ///< the absolute tolerance used for near duplicates

  /// One sentence per defect found ("70 boundary edges (open surface)", ...); empty when clean.
  std::vector<std::string> defects() const;
  /// True when nothing in defects(): closed, manifold, consistently wound outward, no
  /// degenerate/duplicate/unused/non-finite/out-of-range elements. An open surface (a sheet)
  /// is never clean; use is_clean_open() for those.
  bool is_clean() const;
  /// As is_clean() but allows boundary edges and an undefined orientation (open sheets).
  bool is_clean_open() const;
};

/// Checks a mesh in O(V log V + T log T). Never throws on bad input and never reads out of
/// range: out-of-range indices are checked before any topology work.
MeshReport validate(const TriMesh& mesh, const ValidateOptions& options = {});

}  // namespace trocar
