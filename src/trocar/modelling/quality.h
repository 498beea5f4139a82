#pragma once
/// Measures of a built organ surface: distance to a reference surface, triangle shape, genus.
#include <array>
#include <cstddef>

#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Symmetric surface distance between two meshes, sampled at each one's vertices and measured
/// to the other's triangles (exact point-to-triangle distance).
struct SurfaceDistance {
  Real mean = 0;  ///< mean over both directions' samples (m)
  Real max = 0;   ///< Hausdorff distance: the largest sample (m)
};

/// Distance from a's vertices to b's surface and from b's vertices to a's (VTK cell locator).
SurfaceDistance surface_distance(const TriMesh& a, const TriMesh& b);

/// Triangle shape figures.
struct ShapeQuality {
  Real min_angle_deg = 0;   ///< smallest interior angle of any triangle
  Real mean_min_angle_deg = 0;  ///< mean over triangles of their smallest angle
  /// Aspect ratio l_max·(a+b+c)/(4√3·area) (1 for an equilateral triangle; vtkMeshQuality's
  /// triangle aspect ratio), counted in bins [1,1.5) [1.5,2) [2,3) [3,5) [5,10) [10,∞).
  std::array<std::size_t, 6> aspect_histogram{};
  Real max_aspect = 0;      ///< worst aspect ratio
};

/// Upper bounds of the aspect-ratio bins (the last is open).
inline constexpr std::array<Real, 5> kAspectBinEdges{1.5, 2, 3, 5, 10};

/// Angles and aspect ratios of every triangle.
ShapeQuality shape_quality(const TriMesh& mesh);

/// Total genus of a closed mesh from its Euler characteristic χ and component count C:
/// each closed orientable component has χ = 2 − 2g, so g = (2C − χ)/2.
int genus(const TriMesh& mesh);

}  // namespace trocar
