#pragma once
/// Checks ITK does not make: ITK 5.2 reads a truncated or corrupt .nii.gz, a truncated .nii and
/// a truncated compressed MetaImage without a word (the missing voxels come out as zeros), and
/// turns a zero NIfTI pixdim into 1. These read the headers themselves and throw FileError.
#include <string>

namespace trocar {

/// NIfTI-1 (.nii or .nii.gz): the whole gzip stream decompresses with a good CRC, the voxel
/// data is all there (vox_offset + voxels · bitpix/8 bytes), the voxel size is positive.
void check_nifti_file(const std::string& file);

/// MetaImage (.mha or .mhd + data file): the (possibly zlib-compressed) data holds every voxel.
void check_metaimage_file(const std::string& file);

}  // namespace trocar
