#pragma once
/// Seeded random organs in metres for the robustness suite (no external mesh needed): smooth,
/// closed, star-shaped lobes and flattened organs on a geodesic sphere. Every mesh is outward
/// (counter-clockwise seen from outside), validates clean and has no self-intersection by
/// construction (see make_organ_shape). The formula, counts and family are in docs/mesh.md.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Largest frequency make_geodesic_sphere accepts (V = 10·1024² + 2 ≈ 10.5 M, as an icosphere
/// at 10 levels).
inline constexpr std::size_t kMaxGeodesicFrequency = 1024;

/// A class-I geodesic sphere of `radius` (m) centred at the origin: each icosahedron face is
/// split into frequency² triangles by a grid of frequency steps along each edge, the grid
/// points are pushed radially onto the sphere. Edge and corner vertices are shared by
/// construction (one index per icosahedron corner, frequency − 1 per icosahedron edge), never
/// by a tolerance weld. V = 10f² + 2, T = 20f², E = 30f²; frequency 2ⁿ gives the same counts
/// as make_icosphere(radius, n), other frequencies the counts in between (f = 10: 2000 T,
/// f = 35: 24500 T). Outward; per-vertex normals are filled (radial). Throws trocar::Error for
/// radius ≤ 0 or frequency outside [1, kMaxGeodesicFrequency].
TriMesh make_geodesic_sphere(Real radius, std::size_t frequency);

/// The frequency f ≥ 1 whose geodesic sphere's 20f² triangles is nearest `target_triangles`
/// (the smaller f on a tie), at most kMaxGeodesicFrequency.
std::size_t nearest_geodesic_frequency(std::size_t target_triangles);

/// What make_organ_shape builds. The defaults give a 12 cm lobe of 8000 triangles.
struct OrganShapeSpec {
  std::uint64_t seed = 1;              ///< random stream (std::mt19937_64); same seed → same mesh
  std::size_t target_triangles = 8000; ///< wanted T; the nearest 20f² is used (≥ 20)
  Real size = 0.12;                    ///< longest bounding-box extent (m, along x), > 0
  /// Flattening in [0, 0.9]: the z aspect ratio (a random 0.4–0.7 of x) is multiplied by
  /// (1 − flatten). 0 gives a lobe; e.g. 0.6 a flattened organ (z extent 0.16–0.28 of x).
  Real flatten = 0;
  /// Scale of the random radial bumps in [0, 1] (dimensionless; 0 gives a smooth tapered
  /// ellipsoid, 1 the full amplitudes, see make_organ_shape).
  Real roughness = 1;
  std::string name;                    ///< label for reports, e.g. "lobe-2k-s1" (not used to build)
};

/// A smooth random closed organ, deterministic from spec.seed: the draws are our own uniforms
/// from the raw 64-bit words (no std distribution), so they are equal across standard libraries;
/// the positions are bit-identical for a given build (they use std::exp, which C libraries may
/// round differently in the last bit):
///  1. u = the unit vertices of make_geodesic_sphere(1, f), f = nearest_geodesic_frequency(T).
///  2. aspect ratios a_y ∈ [0.6, 0.9], a_z ∈ [0.4, 0.7]·(1 − flatten), D = diag(1, a_y, a_z).
///  3. pre-warp w = normalize(D^(−1/2)·u): thins the directions along the axes D shortens, so
///     the triangles there are not crushed by step 5 (smallest angle 20° rather than 9°).
///  4. p = r(w)·w with r(w) = 1 + λ·[Σ_k a_k·exp(−(1 − w·c_k)/σ_k²) + wᵀQw]: 4–6 Gaussian
///     bumps (random unit centres c_k, widths σ_k ∈ [0.4, 0.8] rad, amplitudes a_k ∈ [−0.3, 0.35])
///     plus a random traceless symmetric quadratic Q (entries drawn in ±0.12, Q_zz = −Q_xx −
///     Q_yy); λ = roughness·min(1, 0.6/H₊, 0.5/H₋), H± = Σ max(±a_k, 0) + ‖Q‖_F, so
///     r ∈ [0.5, 1.6].
///  5. q = D·p, then a perspective taper q ← q/(1 + τ·q_x), τ ∈ [−0.15, 0.15] (one end thicker).
///  6. per-axis scale so the bounding box is size × a_y·size × a_z·size exactly, centred at the
///     origin (x is the longest extent).
/// Steps 3–5 are linear maps with positive determinant, moves of a vertex along its ray from
/// the origin, and the taper (which maps each ray from the origin into itself and planes to
/// planes): each keeps every triangle flat inside its cone over a tiling of the unit sphere,
/// with det(a, b, c) > 0; step 6 is affine. Hence triangles meet only at shared edges and
/// vertices (no self-intersection, by construction, whatever the seed) and the mesh is
/// outward. V = 10f² + 2, T = 20f². No normals. Throws trocar::Error on a bad spec.
TriMesh make_organ_shape(const OrganShapeSpec& spec);

/// The robustness suite's six organs from `seed` (each member's seed mixed from it and its
/// slot): lobe 2000 T 6 cm, flattened 5120 T 10 cm, lobe 8000 T 12 cm, flattened 11520 T
/// 15 cm, lobe 18000 T 14 cm, flattened 24500 T 18 cm (flatten 0.6), named "lobe-2k-s<seed>",
/// "flat-5k-s<seed>", ... (targets 2000, 5000, 8000, 12000, 18000, 24500).
std::vector<OrganShapeSpec> organ_family(std::uint64_t seed = 1);

}  // namespace trocar
