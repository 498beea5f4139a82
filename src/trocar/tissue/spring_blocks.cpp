// Spring quads regrouped by blocks of vertices (spring_blocks.h).
#include "trocar/tissue/spring_blocks.h"

#include <algorithm>

#include "trocar/core/error.h"

namespace trocar::tissue_detail {
namespace {

constexpr std::uint32_t kStride = sizeof(Padded3);

std::uint32_t lowest(const SpringQuad& q) {
  std::uint32_t m = q.i[0];
  for (int k = 0; k < 4; ++k) m = std::min({m, q.i[k], q.j[k]});
  return m / kStride;
}
std::uint32_t highest(const SpringQuad& q) {
  std::uint32_t m = q.i[0];
  for (int k = 0; k < 4; ++k) m = std::max({m, q.i[k], q.j[k]});
  return m / kStride;
}

}  // namespace

BlockedSprings block_springs(const SpringLayout& layout, std::size_t vertex_count, std::size_t block) {
  if (block == 0) throw Error("tissue: a block of vertices must hold at least one");
  const std::size_t n = vertex_count, blocks = (n + block - 1) / block;
  BlockedSprings out;
  std::vector<std::size_t> reach(blocks);
  for (std::size_t b = 0; b < blocks; ++b) reach[b] = std::min(n, (b + 1) * block);

  // Stars: a counting sort by block, stable.
  std::vector<std::uint32_t> start(blocks + 1, 0);
  for (const SpringQuad& q : layout.stars) ++start[lowest(q) / block + 1];
  for (std::size_t b = 0; b < blocks; ++b) start[b + 1] += start[b];
  out.stars_end.assign(start.begin() + 1, start.end());
  out.layout.stars.resize(layout.stars.size());
  for (const SpringQuad& q : layout.stars) {
    const std::size_t b = lowest(q) / block;
    out.layout.stars[start[b]++] = q;
    reach[b] = std::max<std::size_t>(reach[b], highest(q) + 1);
  }

  // The ordinary quads' springs, block by block, in new quads.
  std::vector<std::vector<Spring>> springs(blocks);
  for (const SpringQuad& q : layout.others)
    for (int k = 0; k < 4; ++k) {
      if (q.i[k] == q.j[k]) continue;
      const std::uint32_t i = q.i[k] / kStride, j = q.j[k] / kStride;
      const std::size_t b = std::min(i, j) / block;
      springs[b].push_back({i, j, q.rest_length[k], q.stiffness[k], q.damping[k]});
      reach[b] = std::max<std::size_t>(reach[b], std::max(i, j) + 1);
    }
  out.others_end.resize(blocks);
  for (std::size_t b = 0; b < blocks; ++b) {
    const auto first = static_cast<std::uint32_t>(b * block * kStride);
    for (std::size_t e = 0; e < springs[b].size(); e += 4) {
      SpringQuad& q = out.layout.others.emplace_back();
      for (std::size_t k = 0; k < 4; ++k) {
        q.i[k] = q.j[k] = first;
        if (e + k >= springs[b].size()) continue;
        const Spring& sp = springs[b][e + k];
        q.i[k] = sp.i * kStride;
        q.j[k] = sp.j * kStride;
        q.rest_length[k] = sp.rest_length;
        q.stiffness[k] = sp.stiffness;
        q.damping[k] = sp.damping;
      }
    }
    out.others_end[b] = static_cast<std::uint32_t>(out.layout.others.size());
  }

  out.reach.resize(blocks);
  std::size_t running = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    running = std::max(running, reach[b]);
    out.reach[b] = static_cast<std::uint32_t>(running);
  }
  return out;
}

}  // namespace trocar::tissue_detail
