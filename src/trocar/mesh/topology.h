#pragma once
/// Edge and vertex adjacency of a triangle mesh, in flat arrays (CSR offsets), built once in
/// O(T log T): unique edges, edge → triangles, triangle → edges, vertex → triangles, boundary
/// and non-manifold edges and vertices, connected components and the Euler characteristic.
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// An undirected edge as a sorted vertex pair (v0 < v1).
struct Edge {
  std::uint32_t v0 = 0;  ///< smaller vertex index
  std::uint32_t v1 = 0;  ///< larger vertex index
  friend bool operator==(const Edge&, const Edge&) = default;
};

/// The connectivity of a TriMesh. Conventions:
/// - Local edge k of triangle t joins corners k and (k+1) mod 3 (so it is opposite corner
///   (k+2) mod 3); triangle_edges(t)[k] is its edge id.
/// - A triangle with a repeated index (a, a, b) has a zero-length local edge (a, a); it gets
///   kNone there and the edge (a, b) lists that triangle twice. Drop such triangles first
///   (repair() does) when the adjacency matters.
/// - Edges are numbered in increasing (v0, v1) order; each edge's triangle list is in
///   increasing triangle order.
/// - Components: two triangles are in the same component when they share a vertex (so a
///   bow-tie touching at one vertex is one component). This is the usual notion of "parts";
///   the winding repair in repair.h propagates only across edges, and reports patches.
/// - Every count that involves vertices (Euler characteristic, vertex_used) counts only the
///   vertices some triangle references; unused vertices are neither parts nor components.
/// The mesh's indices must be valid (TriMesh::indices_valid()); the constructor throws
/// trocar::Error otherwise. The topology does not keep a reference to the mesh.
class MeshTopology {
 public:
  /// Marks "no such element" (no edge for a zero-length local edge, no opposite vertex).
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  MeshTopology() = default;
  /// Builds the topology of `mesh` (throws trocar::Error for out-of-range indices).
  explicit MeshTopology(const TriMesh& mesh);

  std::size_t vertex_count() const { return vertex_tri_offsets_.empty() ? 0 : vertex_tri_offsets_.size() - 1; }  ///< V (used or not)
  std::size_t triangle_count() const { return tri_edges_.size(); }  ///< T
  std::size_t edge_count() const { return edges_.size(); }          ///< E (unique, undirected)
  /// Number of vertices referenced by at least one triangle.
  std::size_t used_vertex_count() const { return used_vertex_count_; }

  /// All unique edges, sorted by (v0, v1).
  std::span<const Edge> edges() const { return edges_; }
  /// Edge e's vertex pair.
  const Edge& edge(std::size_t e) const { return edges_[e]; }
  /// The triangles that use edge e (1 = boundary, 2 = interior, > 2 = non-manifold).
  std::span<const std::uint32_t> edge_triangles(std::size_t e) const {
    return {edge_tris_.data() + edge_tri_offsets_[e], edge_tri_offsets_[e + 1] - edge_tri_offsets_[e]};
  }
  /// Number of triangle uses of edge e.
  std::size_t edge_valence(std::size_t e) const { return edge_tri_offsets_[e + 1] - edge_tri_offsets_[e]; }
  /// Triangle t's edge ids, local edge k = corners (k, k+1); kNone for a zero-length edge.
  const std::array<std::uint32_t, 3>& triangle_edges(std::size_t t) const { return tri_edges_[t]; }
  /// The triangles incident to vertex v (each once, increasing order).
  std::span<const std::uint32_t> vertex_triangles(std::size_t v) const {
    return {vertex_tris_.data() + vertex_tri_offsets_[v], vertex_tri_offsets_[v + 1] - vertex_tri_offsets_[v]};
  }
  /// For an interior edge (exactly 2 triangles) the vertex of each triangle opposite the
  /// edge, in the order of edge_triangles(e): the "wing" vertices a bending spring joins.
  /// {kNone, kNone} for any other edge.
  std::array<std::uint32_t, 2> opposite_vertices(std::size_t e) const { return opposite_[e]; }
  /// True when triangle t traverses edge e from edge(e).v0 to edge(e).v1 (its winding).
  /// e must be one of t's edges.
  bool traverses_forward(const TriMesh& mesh, std::size_t t, std::size_t e) const;

  /// Edges with exactly one triangle, increasing id.
  std::span<const std::uint32_t> boundary_edges() const { return boundary_edges_; }
  /// Edges with more than two triangles, increasing id.
  std::span<const std::uint32_t> nonmanifold_edges() const { return nonmanifold_edges_; }
  /// Vertices whose incident triangles form more than one edge-connected fan (e.g. the tip
  /// of a bow-tie, or two cones touching at the apex), increasing id.
  std::span<const std::uint32_t> nonmanifold_vertices() const { return nonmanifold_vertices_; }

  /// Number of vertex-connected components (0 for an empty mesh).
  std::size_t component_count() const { return component_tri_counts_.size(); }
  /// Component id of triangle t, in [0, component_count()); ids follow the lowest triangle
  /// index in each component (component 0 contains triangle 0).
  std::uint32_t triangle_component(std::size_t t) const { return tri_component_[t]; }
  /// Triangle count of each component.
  std::span<const std::uint32_t> component_triangle_counts() const { return component_tri_counts_; }

  /// χ = V_used − E + T (2 for a closed genus-0 surface, 1 for a disc; a sum over components).
  long long euler_characteristic() const {
    return static_cast<long long>(used_vertex_count_) - static_cast<long long>(edges_.size()) +
           static_cast<long long>(tri_edges_.size());
  }

 private:
  std::vector<Edge> edges_;
  std::vector<std::uint32_t> edge_tri_offsets_;  // size E+1
  std::vector<std::uint32_t> edge_tris_;         // size Σ valence (= 3T minus zero-length edges)
  std::vector<std::array<std::uint32_t, 3>> tri_edges_;
  std::vector<std::uint32_t> vertex_tri_offsets_;  // size V+1
  std::vector<std::uint32_t> vertex_tris_;
  std::vector<std::array<std::uint32_t, 2>> opposite_;
  std::vector<std::uint32_t> boundary_edges_;
  std::vector<std::uint32_t> nonmanifold_edges_;
  std::vector<std::uint32_t> nonmanifold_vertices_;
  std::vector<std::uint32_t> tri_component_;
  std::vector<std::uint32_t> component_tri_counts_;
  std::size_t used_vertex_count_ = 0;
};

}  // namespace trocar
