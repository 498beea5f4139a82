#pragma once
/// From a binary mask to a closed organ surface: keep the wanted components, pad, optionally
/// pre-smooth, extract (flying edges), smooth without shrinking (windowed sinc), decimate
/// (topology-preserving edge collapse) to a triangle budget, keep the largest surface. The chain 3D Slicer uses to turn
/// segmentations into closed surface models (docs/modelling.md).
#include <cstddef>
#include <functional>
#include <string>

#include "trocar/mesh/tri_mesh.h"
#include "trocar/modelling/label_select.h"
#include "trocar/modelling/volume.h"

namespace trocar {

/// How the surface is made.
struct SurfaceOptions {
  std::size_t target_triangles = 6000;  ///< decimate to about this many (0: no decimation)
  int smooth_iterations = 20;           ///< windowed-sinc iterations (0: no smoothing)
  /// Windowed-sinc pass band: Slicer's smoothing factor f gives 10^(−4f); its default f = 0.5.
  Real smooth_passband = 0.01;
  /// Gaussian pre-smoothing of the mask before extraction, standard deviation (m); 0: none.
  /// Softens the staircase of thick slices; extraction then runs at the 0.5 level.
  Real presmooth_sigma = 0;
  /// Morphological closing of the mask before anything else, ball radius (m); 0: none. Fills
  /// tunnels, pits and gaps narrower than about twice the radius (noisy labels' small handles).
  Real close_radius = 0;
  /// Keep only the largest 6-connected component of the mask (else every component of at
  /// least `min_component_voxels`).
  bool largest_component_only = true;
  std::size_t min_component_voxels = 8;  ///< smallest kept component (and smallest organ)
  /// Extraction grid stride: 0 = auto (coarser when the full-resolution surface would exceed
  /// ~6× the triangle budget, near-isotropic voxels only), 1 = full resolution, s = every s-th
  /// voxel of the block-averaged mask.
  int extract_stride = 0;
  /// Rounds of isotropic remeshing that bring the smoothed surface to the budget with
  /// near-equilateral triangles (about target_triangles, within a few per cent); 0: decimate by
  /// edge collapse instead (exactly target_triangles, but slivers: minimum angles of 0.1–6°).
  int remesh_iterations = 3;
  /// Also extract the full-resolution surface as the reference for the distance figures (it
  /// is the extracted surface itself when the stride is 1).
  bool reference_surface = true;
};

/// Seconds each stage took.
struct SurfaceTimes {
  double components = 0;  ///< connected components of the mask
  double extract = 0;     ///< padding, pre-smoothing and flying edges
  double smooth = 0;      ///< windowed sinc
  double decimate = 0;    ///< remeshing or edge-collapse decimation to the budget
  double clean = 0;       ///< largest surface, compaction, world mapping
};

/// What extract_surface() made.
struct Surface {
  /// The full-resolution extracted surface (world, m): the reference the distances are measured
  /// against; empty when the stride was > 1 and reference_surface was off.
  TriMesh raw;
  TriMesh mesh;                  ///< the final surface (world, m), outward
  std::size_t kept_voxels = 0;     ///< voxels of the kept components
  std::size_t components = 0;      ///< 6-connected components in the mask
  std::size_t components_kept = 0; ///< of them, kept
  int stride = 1;                  ///< extraction grid stride used
  double thickness_voxels = 0;     ///< kept voxels / boundary faces (a thickness scale)
  double edge_voxels = 0;          ///< edge length of an equilateral mesh at the budget (voxels)
  std::string decimator;           ///< how it was decimated, or "none"
  SurfaceTimes times;              ///< seconds per stage
};

/// Called with a stage name and the fraction done of it (0..1).
using ProgressFn = std::function<void(const std::string& stage, double fraction)>;

/// Makes the surface of `mask` on `volume`'s grid. Throws FileError naming volume.source when
/// the kept part is smaller than min_component_voxels or the surface comes out empty.
Surface extract_surface(const Volume& volume, const Mask& mask, const SurfaceOptions& options,
                        const ProgressFn& progress = {});

}  // namespace trocar
