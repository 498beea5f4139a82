#pragma once
/// Topology-safe decimation: edge collapses that never make a surface non-manifold.
#include <cstddef>

#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Collapses edges of a closed manifold mesh until it has at most `target_triangles`, by
/// Lindstrom–Turk cost and placement (volume- and shape-preserving quadric optimisation;
/// CGAL's Surface_mesh_simplification). Every collapse is checked against the link condition,
/// so the result keeps the input's topology: closed, manifold, same genus. A bounded-normal-
/// change filter refuses collapses that would flip a triangle. Stops early where no collapse
/// is allowed (a tiny genus-g surface cannot go below its minimal triangulation).
TriMesh decimate_preserving_topology(const TriMesh& mesh, std::size_t target_triangles);

/// Isotropic remeshing towards equilateral triangles of the edge length that gives about
/// about `target_triangles` on this surface's area (l = 1.1·√(4A / (√3·N))): edge splits,
/// collapses and flips with tangential relaxation, each vertex projected back onto the input
/// surface (CGAL's Polygon_mesh_processing::isotropic_remeshing, `iterations` rounds).
/// Collapses keep the link condition, so topology is kept.
TriMesh remesh_isotropic(const TriMesh& mesh, std::size_t target_triangles, int iterations);

}  // namespace trocar
