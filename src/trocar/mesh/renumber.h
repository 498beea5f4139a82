#pragma once
/// Vertex renumbering for memory locality. The tissue integrators read and write each vertex's
/// state once per spring end (gathers and scatters through the spring list); when the vertices
/// that share springs are near one another in memory, those accesses stay in the same cache
/// lines and pages. A file's own vertex order is often not local (measured on the shared meshes:
/// a step 3–5 % faster with the order below, docs/tissue-integrators.md "Vertex order").
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// A Cuthill–McKee order of the mesh's vertices: breadth first over the edge graph, each
/// component started from a pseudo-peripheral vertex (the last one reached by a breadth-first
/// pass from its lowest-index vertex), neighbours taken by increasing degree (ties by index),
/// components in the order of their lowest vertex index. Vertices no triangle uses come last, in
/// index order. order[new] = old; deterministic. Throws trocar::Error for invalid indices.
std::vector<std::uint32_t> locality_vertex_order(const TriMesh& mesh);

/// The mesh with vertex order[k] as vertex k: positions and normals permuted, triangle indices
/// renamed (triangle order, winding and per-corner texcoords unchanged). `order` must be a
/// permutation of the vertex indices (throws trocar::Error otherwise).
TriMesh renumber_vertices(const TriMesh& mesh, std::span<const std::uint32_t> order);

/// The inverse permutation: inverse[order[k]] = k (new index of each old vertex).
std::vector<std::uint32_t> inverse_order(std::span<const std::uint32_t> order);

}  // namespace trocar
