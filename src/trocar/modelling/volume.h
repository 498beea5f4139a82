#pragma once
/// A scalar image volume in world space: a label map or a grey-value scan, as read from a
/// medical image file or made in code. World coordinates are patient LPS (DICOM's and ITK's
/// convention: +x left, +y posterior, +z superior) in metres: NIfTI's RAS is converted on
/// reading, as ITK does.
#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// One or more layers of voxel values on a regular grid; x varies fastest.
struct Volume {
  std::array<std::size_t, 3> dims{0, 0, 0};  ///< voxels along the index axes i, j, k
  Vec3 spacing = Vec3::Ones();               ///< voxel size along i, j, k (m)
  Vec3 origin = Vec3::Zero();                ///< world position of voxel (0,0,0)'s centre (m)
  Mat3 direction = Mat3::Identity();         ///< columns: the index axes' unit directions in world
  /// Voxel values, one vector of dims[0]·dims[1]·dims[2] per layer (a Slicer .seg.nrrd with
  /// overlapping segments has several; every other file one).
  std::vector<std::vector<float>> layers;
  /// Segment names the file gives (Slicer segment metadata, a NIfTI label-table extension), by
  /// (layer, label value); empty when the file names none.
  std::map<std::pair<int, int>, std::string> names;
  std::string source;  ///< file name (or a description) for messages

  std::size_t voxel_count() const { return dims[0] * dims[1] * dims[2]; }
  /// Linear index of voxel (i, j, k).
  std::size_t index(std::size_t i, std::size_t j, std::size_t k) const { return i + dims[0] * (j + dims[1] * k); }
  /// World position of a (fractional) index point: origin + D·diag(spacing)·ijk.
  Vec3 index_to_world(const Vec3& ijk) const { return origin + direction * spacing.cwiseProduct(ijk); }
  /// Volume of one voxel (m³).
  Real voxel_volume() const { return spacing.prod(); }
};

/// Builds a one-layer volume of the given size filled with `fill`, identity direction.
Volume make_volume(std::array<std::size_t, 3> dims, const Vec3& spacing, const Vec3& origin, float fill = 0);

/// Reads NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr, Slicer .seg.nrrd with its segment names and
/// layers) or MetaImage (.mha, .mhd + .raw/.zraw) through ITK, with spacing, origin and direction;
/// millimetres become metres. Throws FileError naming the file and the reason for a missing
/// file, an unknown format, a corrupt or truncated stream, a zero or non-finite spacing, or a
/// volume that is not 3-D.
Volume read_volume(const std::filesystem::path& path);

/// Writes layer 0 through ITK, the format from the extension (.nii.gz, .nii, .nrrd, .mha);
/// values rounded to unsigned 8-bit when every value is an integer in [0, 255], else float.
/// Throws FileError when the file cannot be written.
void write_volume(const Volume& volume, const std::filesystem::path& path);

}  // namespace trocar
