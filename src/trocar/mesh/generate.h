#pragma once
/// Procedural meshes in metres: test shapes, a peritoneum sheet and instrument shafts.
/// Closed meshes are outward-oriented (counter-clockwise seen from outside) and validate clean.
/// Counts for each generator are in docs/mesh.md and beside each function.
#include <cstddef>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// A sphere of `radius` centred at the origin: the icosahedron subdivided `subdivisions`
/// times (each level splits every triangle into 4, new vertices pushed onto the sphere).
/// V = 10·4ⁿ + 2, T = 20·4ⁿ, E = 30·4ⁿ (n = 0: 12 V, 20 T). Vertices lie on the sphere;
/// per-vertex normals are filled (radial). Throws trocar::Error for radius ≤ 0 or n > 10.
TriMesh make_icosphere(Real radius, int subdivisions);

/// An open rectangular sheet in the xy plane, centred at the origin, x ∈ [−w/2, w/2],
/// y ∈ [−h/2, h/2], nx × ny cells, each split into two triangles along alternating diagonals.
/// z = bulge_height · cos²(πx/w) · cos²(πy/h) (0 on the border, bulge_height at the centre;
/// 0 gives a flat sheet). Wound counter-clockwise seen from +z (normals +z when flat).
/// V = (nx+1)(ny+1), T = 2·nx·ny, boundary edges 2(nx+ny), χ = 1. No normals.
TriMesh make_sheet(Real width, Real height, std::size_t nx, std::size_t ny, Real bulge_height = 0);

/// A capsule: all points within `radius` of the segment (0,0,0)–(0,0,length) (z ∈ [−r, L+r]).
/// `segments` around the axis (≥ 3), `rings` latitude bands per hemisphere (≥ 1).
/// V = 2·rings·segments + 2, T = 4·rings·segments. No normals.
TriMesh make_capsule(Real radius, Real length, std::size_t segments, std::size_t rings);

/// A cylinder of `radius` along +z, z ∈ [0, length], `segments` (≥ 3) around. Capped: closed,
/// V = 2s + 2 (two cap centres), T = 4s; uncapped: open tube, V = 2s, T = 2s, 2s boundary
/// edges. Volume (capped) = ½·s·r²·sin(2π/s)·length exactly. No normals.
TriMesh make_cylinder(Real radius, Real length, std::size_t segments, bool capped = true);

/// An axis-aligned box of size sx × sy × sz centred at the origin: 8 V, 12 T.
TriMesh make_box(Real sx, Real sy, Real sz);

}  // namespace trocar
