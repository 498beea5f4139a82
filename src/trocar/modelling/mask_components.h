#pragma once
/// Connected components of a binary mask (ITK), numbered by size.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace trocar {

/// The mask's 6-connected components (what the 0.5 iso-surface joins), numbered 1, 2, … from
/// the largest down (0 = outside); `sizes[c]` is the voxel count of component c + 1.
struct Components {
  std::vector<std::uint32_t> labels;  ///< per voxel, same indexing as the mask
  std::vector<std::size_t> sizes;     ///< voxels per component, largest first
};

/// ITK's ConnectedComponentImageFilter then RelabelComponentImageFilter.
Components connected_components(const std::vector<std::uint8_t>& mask, const std::array<std::size_t, 3>& dims);

/// Morphological closing (dilate then erode) by an ellipsoidal ball of the given radii in
/// voxels (ITK's BinaryMorphologicalClosingImageFilter, safe border): fills gaps, pits and
/// tunnels narrower than the ball, so a noisy label loses its small handles.
std::vector<std::uint8_t> close_mask(const std::vector<std::uint8_t>& mask, const std::array<std::size_t, 3>& dims,
                                     const std::array<unsigned, 3>& radius);

}  // namespace trocar
