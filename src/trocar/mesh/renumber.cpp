#include "trocar/mesh/renumber.h"

#include <algorithm>
#include <string>

#include "trocar/core/error.h"
#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

/// Vertex adjacency over the unique edges, in CSR form, each list sorted by (degree, index).
struct Adjacency {
  std::vector<std::uint32_t> offsets, neighbours;
  std::uint32_t degree(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
  std::span<const std::uint32_t> of(std::uint32_t v) const {
    return std::span(neighbours).subspan(offsets[v], degree(v));
  }
};

Adjacency adjacency(const MeshTopology& topology, std::size_t vertex_count) {
  Adjacency a;
  a.offsets.assign(vertex_count + 1, 0);
  for (const Edge& e : topology.edges()) {
    ++a.offsets[e.v0 + 1];
    ++a.offsets[e.v1 + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) a.offsets[v + 1] += a.offsets[v];
  a.neighbours.resize(a.offsets.back());
  std::vector<std::uint32_t> fill(a.offsets.begin(), a.offsets.end() - 1);
  for (const Edge& e : topology.edges()) {
    a.neighbours[fill[e.v0]++] = e.v1;
    a.neighbours[fill[e.v1]++] = e.v0;
  }
  for (std::size_t v = 0; v < vertex_count; ++v) {
    auto begin = a.neighbours.begin() + a.offsets[v], end = a.neighbours.begin() + a.offsets[v + 1];
    std::sort(begin, end, [&](std::uint32_t x, std::uint32_t y) {
      return a.degree(x) < a.degree(y) || (a.degree(x) == a.degree(y) && x < y);
    });
  }
  return a;
}

/// Breadth-first from `start` over the vertices not yet `placed`, appending them to `order`
/// (and marking them); returns the last vertex reached.
std::uint32_t breadth_first(const Adjacency& a, std::uint32_t start, std::vector<std::uint8_t>& placed,
                            std::vector<std::uint32_t>& order) {
  std::size_t head = order.size();
  order.push_back(start);
  placed[start] = 1;
  while (head < order.size()) {
    const std::uint32_t v = order[head++];
    for (const std::uint32_t w : a.of(v))
      if (!placed[w]) {
        placed[w] = 1;
        order.push_back(w);
      }
  }
  return order.back();
}

}  // namespace

std::vector<std::uint32_t> locality_vertex_order(const TriMesh& mesh) {
  const std::size_t n = mesh.vertex_count();
  const MeshTopology topology(mesh);
  const Adjacency a = adjacency(topology, n);
  std::vector<std::uint32_t> order;
  order.reserve(n);
  std::vector<std::uint8_t> placed(n, 0), probe_placed(n, 0);
  std::vector<std::uint32_t> probe;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (placed[v] || a.degree(v) == 0) continue;
    // A first pass from the component's lowest vertex finds a far (pseudo-peripheral) vertex.
    probe.clear();
    const std::uint32_t far = breadth_first(a, v, probe_placed, probe);
    breadth_first(a, far, placed, order);
  }
  for (std::uint32_t v = 0; v < n; ++v)
    if (!placed[v]) order.push_back(v);
  return order;
}

std::vector<std::uint32_t> inverse_order(std::span<const std::uint32_t> order) {
  std::vector<std::uint32_t> inverse(order.size(), static_cast<std::uint32_t>(-1));
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (order[k] >= order.size() || inverse[order[k]] != static_cast<std::uint32_t>(-1))
      throw Error("renumber_vertices: the order is not a permutation of " + std::to_string(order.size()) +
                  " vertices (entry " + std::to_string(k) + " is " + std::to_string(order[k]) + ")");
    inverse[order[k]] = static_cast<std::uint32_t>(k);
  }
  return inverse;
}

TriMesh renumber_vertices(const TriMesh& mesh, std::span<const std::uint32_t> order) {
  if (order.size() != mesh.vertex_count())
    throw Error("renumber_vertices: " + std::to_string(order.size()) + " entries for " +
                std::to_string(mesh.vertex_count()) + " vertices");
  if (!mesh.indices_valid()) throw Error("renumber_vertices: the mesh has invalid indices or attribute sizes");
  const std::vector<std::uint32_t> new_index = inverse_order(order);
  TriMesh out = mesh;
  for (std::size_t k = 0; k < order.size(); ++k) out.positions[k] = mesh.positions[order[k]];
  if (!mesh.normals.empty())
    for (std::size_t k = 0; k < order.size(); ++k) out.normals[k] = mesh.normals[order[k]];
  for (Triangle& t : out.triangles)
    for (std::uint32_t& v : t) v = new_index[v];
  return out;
}

}  // namespace trocar
