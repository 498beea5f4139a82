#pragma once
/// A spring layout (explicit_kernels.h) regrouped by blocks of consecutive vertices, each quad in
/// the block of its lowest vertex, for passes that sweep the vertices once and interleave
/// per-vertex work with the springs (explicit_sweep.h). With the vertices in a banded order
/// (mesh/renumber.h) a block's quads reach only a little past it.
/// Internal to the tissue module.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trocar/tissue/explicit_kernels.h"

namespace trocar::tissue_detail {

struct BlockedSprings {
  SpringLayout layout;             ///< stars and others, block by block
  /// Per block: where its stars and others end in the layout, and 1 + the highest vertex the
  /// quads of it and every earlier block touch (at least the block's own end; non-decreasing).
  std::vector<std::uint32_t> stars_end, others_end, reach;
};

/// Stars keep their quads (stable within a block). The ordinary quads' springs (null lanes, i = j,
/// dropped: their force is exactly zero) are put in new quads per block, each block's last quad
/// completed with null springs at the block's first vertex. Throws trocar::Error for block 0.
BlockedSprings block_springs(const SpringLayout& layout, std::size_t vertex_count, std::size_t block);

}  // namespace trocar::tissue_detail
