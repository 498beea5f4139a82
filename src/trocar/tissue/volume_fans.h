#pragma once
/// The volume term's triangle pass in fans of four triangles around a shared vertex, for the
/// explicit and implicit steps' padded layout (explicit_kernels.h). Internal to the tissue module.
///
/// The pass computes 6V and g_i = Σ_{t∋i} n_t (n_t = (b − a) × (c − a), twice the area
/// vector). Triangle by triangle that is three loads and three read-modify-writes of g per
/// triangle, which is what the pass is bound by. Four consecutive triangles around a vertex c,
/// (c, r0, r1), (c, r1, r2), (c, r2, r3), (c, r3, r4), share c and the inner ring vertices r1,
/// r2, r3: loaded once, each of the six written once, so 6 loads and 6 read-modify-writes
/// instead of 12 of each; and each edge vector is permuted once for the cross products.
#include <cstdint>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/explicit_kernels.h"

namespace trocar::tissue_detail {

/// Four triangles (c, r_k, r_{k+1}), k = 0..3, each a cyclic rotation of a mesh triangle (so
/// with the same n_t). Vertices as byte offsets into a Padded3 array (index × 32).
struct TriangleFan {
  std::uint32_t center = 0;
  std::uint32_t ring[5] = {};
};

/// The mesh's triangles as fans (greedily, vertex by vertex, runs of four consecutive
/// triangles around it) and the triangles left over, each exactly once.
struct VolumeLayout {
  std::vector<TriangleFan> fans;
  std::vector<Triangle> singles;
  std::uint32_t origin = 0;  ///< the first triangle's first vertex: 6V is taken about it
};
VolumeLayout make_volume_layout(const std::vector<Triangle>& triangles, std::size_t vertex_count);

/// g_i += Σ_{t∋i} n_t, and returns 6V about layout.origin (forces.cpp's volume_of × 6, to
/// rounding: the sum runs in another order). Nothing, and 0, for an empty layout.
Real add_volume_gradient(const VolumeLayout& layout, const Padded3* x, Padded3* g, bool use_avx2);

}  // namespace trocar::tissue_detail
