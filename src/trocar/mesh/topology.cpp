#include "trocar/mesh/topology.h"

#include <algorithm>
#include <numeric>

#include "trocar/core/error.h"

namespace trocar {
namespace {

/// Union-find over 0..n−1 with path halving and union by lower root (so the root of a set is
/// its lowest element, which keeps component numbering deterministic).
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) parent_[b] = a; else parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

}  // namespace

MeshTopology::MeshTopology(const TriMesh& mesh) {
  const std::size_t n_vertices = mesh.positions.size();
  const std::size_t n_tris = mesh.triangles.size();
  if (n_tris >= kNone / 3) throw Error("mesh topology: too many triangles");
  for (const Triangle& tri : mesh.triangles)
    for (std::uint32_t i : tri)
      if (i >= n_vertices)
        throw Error("mesh topology: a triangle index (" + std::to_string(i) +
                    ") is out of range (" + std::to_string(n_vertices) + " vertices)");

  // Half-edges: (sorted vertex pair, 3·t + k), sorted by key then triangle; runs of equal
  // keys are the unique edges. O(T log T), three flat arrays, no per-edge allocation.
  struct HalfEdge {
    std::uint64_t key;
    std::uint32_t corner;  // 3·t + k
  };
  std::vector<HalfEdge> half;
  half.reserve(3 * n_tris);
  tri_edges_.assign(n_tris, {kNone, kNone, kNone});
  for (std::size_t t = 0; t < n_tris; ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      if (a != b) half.push_back({edge_key(a, b), static_cast<std::uint32_t>(3 * t + k)});
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.corner < y.corner;
  });
  edge_tris_.reserve(half.size());
  edge_tri_offsets_.push_back(0);
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (i == 0 || half[i].key != half[i - 1].key) {
      if (i != 0) edge_tri_offsets_.push_back(static_cast<std::uint32_t>(edge_tris_.size()));
      edges_.push_back({static_cast<std::uint32_t>(half[i].key >> 32),
                        static_cast<std::uint32_t>(half[i].key & 0xffffffffu)});
    }
    const std::uint32_t t = half[i].corner / 3, k = half[i].corner % 3;
    tri_edges_[t][k] = static_cast<std::uint32_t>(edges_.size() - 1);
    edge_tris_.push_back(t);
  }
  if (!half.empty()) edge_tri_offsets_.push_back(static_cast<std::uint32_t>(edge_tris_.size()));

  // Per-edge classification and wing vertices.
  opposite_.assign(edges_.size(), {kNone, kNone});
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const auto tris = edge_triangles(e);
    if (tris.size() == 1) boundary_edges_.push_back(static_cast<std::uint32_t>(e));
    if (tris.size() > 2) nonmanifold_edges_.push_back(static_cast<std::uint32_t>(e));
    if (tris.size() == 2 && tris[0] != tris[1]) {
      for (int side = 0; side < 2; ++side) {
        const Triangle& tri = mesh.triangles[tris[side]];
        for (std::uint32_t v : tri)
          if (v != edges_[e].v0 && v != edges_[e].v1) opposite_[e][side] = v;
      }
    }
  }

  // Vertex → triangles by counting sort (each triangle once per distinct corner).
  vertex_tri_offsets_.assign(n_vertices + 1, 0);
  auto distinct = [](const Triangle& tri, std::uint32_t k) {
    return k == 0 || (k == 1 && tri[1] != tri[0]) || (k == 2 && tri[2] != tri[0] && tri[2] != tri[1]);
  };
  for (const Triangle& tri : mesh.triangles)
    for (std::uint32_t k = 0; k < 3; ++k)
      if (distinct(tri, k)) ++vertex_tri_offsets_[tri[k] + 1];
  for (std::size_t v = 0; v < n_vertices; ++v) {
    if (vertex_tri_offsets_[v + 1] != 0) ++used_vertex_count_;
    vertex_tri_offsets_[v + 1] += vertex_tri_offsets_[v];
  }
  vertex_tris_.resize(vertex_tri_offsets_[n_vertices]);
  {
    std::vector<std::uint32_t> fill(vertex_tri_offsets_.begin(), vertex_tri_offsets_.end() - 1);
    for (std::size_t t = 0; t < n_tris; ++t)
      for (std::uint32_t k = 0; k < 3; ++k)
        if (distinct(mesh.triangles[t], k))
          vertex_tris_[fill[mesh.triangles[t][k]]++] = static_cast<std::uint32_t>(t);
  }

  // Non-manifold vertices: union-find over corners (3·t + k); the corners at v of two
  // triangles sharing an edge through v are joined. A vertex whose corners form more than one
  // set has more than one fan. O(T α(T)).
  {
    DisjointSets corners(3 * n_tris);
    auto corner_of = [&](std::uint32_t t, std::uint32_t v) {
      const Triangle& tri = mesh.triangles[t];
      const std::uint32_t k = tri[0] == v ? 0u : (tri[1] == v ? 1u : 2u);
      return 3 * t + k;
    };
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const auto tris = edge_triangles(e);
      for (std::size_t i = 1; i < tris.size(); ++i)
        for (std::uint32_t v : {edges_[e].v0, edges_[e].v1})
          corners.unite(corner_of(tris[0], v), corner_of(tris[i], v));
    }
    for (std::size_t v = 0; v < n_vertices; ++v) {
      const auto tris = vertex_triangles(v);
      if (tris.size() < 2) continue;
      const std::uint32_t root = corners.find(corner_of(tris[0], static_cast<std::uint32_t>(v)));
      for (std::size_t i = 1; i < tris.size(); ++i)
        if (corners.find(corner_of(tris[i], static_cast<std::uint32_t>(v))) != root) {
          nonmanifold_vertices_.push_back(static_cast<std::uint32_t>(v));
          break;
        }
    }
  }

  // Components: triangles sharing a vertex (union-find over vertices).
  {
    DisjointSets vertices(n_vertices);
    for (const Triangle& tri : mesh.triangles) {
      vertices.unite(tri[0], tri[1]);
      vertices.unite(tri[0], tri[2]);
    }
    std::vector<std::uint32_t> id_of_root(n_vertices, kNone);
    tri_component_.resize(n_tris);
    for (std::size_t t = 0; t < n_tris; ++t) {
      const std::uint32_t root = vertices.find(mesh.triangles[t][0]);
      if (id_of_root[root] == kNone) {
        id_of_root[root] = static_cast<std::uint32_t>(component_tri_counts_.size());
        component_tri_counts_.push_back(0);
      }
      tri_component_[t] = id_of_root[root];
      ++component_tri_counts_[id_of_root[root]];
    }
  }
}

bool MeshTopology::traverses_forward(const TriMesh& mesh, std::size_t t, std::size_t e) const {
  const Triangle& tri = mesh.triangles[t];
  for (std::uint32_t k = 0; k < 3; ++k)
    if (tri_edges_[t][k] == e) return tri[k] == edges_[e].v0;
  return false;
}

}  // namespace trocar
