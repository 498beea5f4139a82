#pragma once
/// Label volumes made in code: analytic shapes with known volume and genus (for testing the
/// pipeline) and an abdominal phantom (a liver with a gallbladder under it) that the shipped
/// scene builds its liver from. Sizes in metres; world = index space scaled, identity direction.
#include <functional>
#include <string>
#include <vector>

#include "trocar/modelling/volume.h"

namespace trocar {

/// A phantom: the volume, and per label its analytic enclosed volume and genus.
struct Phantom {
  Volume volume;
  struct Part {
    int label;          ///< label value
    std::string name;   ///< segment name
    Real volume;        ///< analytic enclosed volume of the labelled region (m³)
    int genus;          ///< its genus
  };
  std::vector<Part> parts;  ///< one per label
};

/// Labels each voxel whose centre satisfies `inside` (world point → label, 0 = background).
Volume rasterise(std::array<std::size_t, 3> dims, Real voxel, const Vec3& origin,
                 const std::function<int(const Vec3&)>& label_at);

/// Sphere of radius r (default 20 mm) on a grid of `voxel`-sized voxels.
Phantom sphere_phantom(Real voxel = 1e-3, Real radius = 0.02);
/// Ellipsoid with semi-axes 40 × 25 × 15 mm, rotated off the grid axes.
Phantom ellipsoid_phantom(Real voxel = 1e-3);
/// Torus, major radius 25 mm, minor 9 mm: genus 1.
Phantom torus_phantom(Real voxel = 1e-3);
/// Two touching blobs with different labels: label 1 a sphere, label 2 a second sphere less
/// the part inside the first (they share a face, as organs do in a label map).
Phantom touching_blobs_phantom(Real voxel = 1e-3);
/// A sphere cut by the volume's first slice: the label touches the volume's edge. Its analytic
/// volume is that of the sphere above the first voxels' lower face (where a padded extraction
/// closes it).
Phantom edge_phantom(Real voxel = 1e-3);
/// An abdominal phantom at `voxel` spacing: label 1 liver (a wedge: thick right lobe tapering to
/// a thin left lobe, domed above, flatter below),
/// label 2 gallbladder tucked under the right lobe. Volumes are those of the rasterised voxels.
Phantom abdomen_phantom(Real voxel = 2e-3);

/// The named phantoms: "sphere", "ellipsoid", "torus", "touching-blobs", "edge", "abdomen".
Phantom make_phantom(const std::string& name, Real voxel);
/// Their names, for help texts.
const std::vector<std::string>& phantom_names();

}  // namespace trocar
