#pragma once
/// Procedural anatomy in metres for the shipped scenes (no file from ../shared needed): a
/// peritoneum sheet with a hernia sac, an abdominal wall patch with a hernia defect and a
/// liver-like lobe. Closed meshes are outward-oriented and validate clean; open sheets are
/// wound counter-clockwise seen from +z and validate clean_open. Counts are beside each function.
#include <cstddef>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// A peritoneum sheet in the plane z = 0, x ∈ [−w/2, w/2], y ∈ [−h/2, h/2], with a hernia sac
/// bulging toward +z through a circular neck of radius `sac_radius` (m) centred at the origin.
/// The sac is the half-ellipsoid ρ = R·sin α, z = depth·cos α, α ∈ [0, π/2] (apex at
/// (0, 0, depth), a finger when depth > R, a dome when depth ≤ R). The flat part is an annulus
/// blended linearly from the neck circle (s = 0) to the rectangle's border (s = 1) along rays.
/// `segments` (a multiple of 4, ≥ 8) vertices per ring, the border's corners among them;
/// `sac_rings` (≥ 1) rings on the sac (the last is the neck), `sheet_rings` (≥ 1) rings from
/// the neck outward (the last is the border). With K = sac_rings + sheet_rings:
/// V = 1 + segments·K, T = segments·(2K − 1), boundary edges = segments, χ = 1.
/// Open, one component, counter-clockwise seen from +z (the sac's outside faces +z).
/// Throws trocar::Error on bad sizes (R ≥ min(w, h)/2, depth ≤ 0, ...).
TriMesh make_hernia_peritoneum(Real width, Real height, Real sac_radius, Real sac_depth, std::size_t segments,
                               std::size_t sac_rings, std::size_t sheet_rings);

/// An abdominal wall patch centred at the origin, x ∈ [−w/2, w/2], y ∈ [−h/2, h/2], with a
/// circular opening (hernia defect) of radius `hole_radius` (m) about the z axis. The same
/// annulus grid as make_hernia_peritoneum: `segments` (a multiple of 4, ≥ 8) per ring, `rings`
/// (≥ 1) bands from the hole to the border.
///  - thickness = 0: an open sheet at z = 0, counter-clockwise seen from +z:
///    V = segments·(rings + 1), T = 2·segments·rings, boundary edges 2·segments, χ = 0.
///  - thickness > 0: a closed slab z ∈ [−t/2, t/2] (a torus topologically), outward:
///    V = 2·segments·(rings + 1), T = 4·segments·(rings + 1), χ = 0,
///    volume = (w·h − hole polygon area)·t, the hole polygon inscribed in the circle.
TriMesh make_abdominal_wall(Real width, Real height, Real thickness, Real hole_radius, std::size_t segments,
                            std::size_t rings);

/// A liver-like closed lobe centred at the origin: an icosphere (`subdivisions` levels) mapped
/// to the ellipsoid of semi-axes a = length/2 (x), b = width/2 (y), c = thickness/2 (z), its
/// underside (z < 0) flattened by `flatten` ∈ (0, 1] and its thickness tapered along x by
/// `taper` ∈ [0, 1): z ← z·(1 − taper·x/a) (thicker at −x, like a right lobe).
/// The map is one-to-one with a positive Jacobian, so the lobe stays closed and outward.
/// V = 10·4ⁿ + 2, T = 20·4ⁿ. Volume → (2/3)·π·a·b·c·(1 + flatten) (the taper's linear term
/// integrates to zero), approached from below. No normals.
TriMesh make_liver_lobe(Real length, Real width, Real thickness, int subdivisions, Real flatten = 0.5,
                        Real taper = 0.3);

}  // namespace trocar
