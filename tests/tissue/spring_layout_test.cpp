// The AVX2 passes' spring layout (explicit_kernels.h): every spring lands in exactly one quad
// lane with its own rest length, stiffness and damping; a star quad's four springs share their
// first vertex; padding lanes add nothing; indices the 32-bit byte offsets cannot address are
// an error, not a silent wrap.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <utility>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/tissue/explicit_kernels.h"

namespace trocar {
namespace {

using tissue_detail::Padded3;
using tissue_detail::SpringQuad;

MassSpringSettings sphere_settings() {
  MassSpringMaterial m;
  m.mass = 0.1;
  m.k_structural = 100;
  m.k_bending = 10;
  m.spring_damping = 0.01;
  return MassSpringSettings::build(make_icosphere(0.03, 2), m);
}

/// (min, max) vertex pair → how many lanes hold it, from the byte offsets.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> lanes_by_pair(const std::vector<SpringQuad>& quads,
                                                                      const MassSpringSettings& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
  for (const SpringQuad& q : quads)
    for (int k = 0; k < 4; ++k) {
      if (q.stiffness[k] == 0 && q.damping[k] == 0) {  // padding: vertex 0 to itself
        EXPECT_EQ(q.i[k], 0u);
        EXPECT_EQ(q.j[k], 0u);
        continue;
      }
      const std::uint32_t a = q.i[k] / sizeof(Padded3), b = q.j[k] / sizeof(Padded3);
      EXPECT_EQ(q.i[k] % sizeof(Padded3), 0u);
      ++count[{std::min(a, b), std::max(a, b)}];
      // The lane carries that spring's own parameters.
      const auto it = std::find_if(s.springs.begin(), s.springs.end(), [&](const Spring& sp) {
        return std::min(sp.i, sp.j) == std::min(a, b) && std::max(sp.i, sp.j) == std::max(a, b);
      });
      EXPECT_NE(it, s.springs.end());
      if (it != s.springs.end()) {
        EXPECT_EQ(q.rest_length[k], it->rest_length);
        EXPECT_EQ(q.stiffness[k], it->stiffness);
        EXPECT_EQ(q.damping[k], it->damping);
      }
    }
  return count;
}

TEST(SpringLayout, EverySpringOnceAndStarsShareTheirFirstVertex) {
  const MassSpringSettings s = sphere_settings();
  ASSERT_GT(s.springs.size(), 100u);
  const tissue_detail::SpringLayout layout = tissue_detail::make_spring_layout(s.springs, s.vertex_count());
  std::vector<SpringQuad> all = layout.stars;
  all.insert(all.end(), layout.others.begin(), layout.others.end());
  const auto count = lanes_by_pair(all, s);
  EXPECT_EQ(count.size(), s.springs.size());  // no spring joins the same pair twice on a sphere
  for (const auto& [pair, n] : count) EXPECT_EQ(n, 1) << pair.first << "-" << pair.second;
  for (const SpringQuad& q : layout.stars)
    for (int k = 1; k < 4; ++k) EXPECT_EQ(q.i[k], q.i[0]);
  // Most springs go into stars (each vertex of an icosphere has 10 to 12 springs).
  EXPECT_GT(layout.stars.size() * 4, s.springs.size() * 8 / 10);
  EXPECT_LE(layout.others.size() * 4, s.springs.size() / 5 + 3);
}

TEST(SpringLayout, SpringsBetweenTwoFixedVerticesAreLeftOut) {
  const MassSpringSettings s = sphere_settings();
  std::vector<std::uint8_t> fixed(s.vertex_count(), 0);
  for (std::size_t i = 0; i < s.vertex_count(); ++i) fixed[i] = s.rest_positions[i].z() < -0.015 ? 1 : 0;
  std::size_t both = 0, one = 0;
  for (const Spring& sp : s.springs) {
    both += fixed[sp.i] && fixed[sp.j];
    one += fixed[sp.i] != fixed[sp.j];
  }
  ASSERT_GT(both, 10u);
  ASSERT_GT(one, 10u);
  const tissue_detail::SpringLayout layout = tissue_detail::make_spring_layout(s.springs, s.vertex_count(), &fixed);
  std::vector<SpringQuad> all = layout.stars;
  all.insert(all.end(), layout.others.begin(), layout.others.end());
  const auto count = lanes_by_pair(all, s);
  EXPECT_EQ(count.size(), s.springs.size() - both);
  for (const auto& [pair, n] : count) {
    EXPECT_EQ(n, 1);
    EXPECT_FALSE(fixed[pair.first] && fixed[pair.second]) << pair.first << "-" << pair.second;
  }
}

TEST(SpringLayout, PlainQuadsKeepTheOrderAndPadTheLastQuad) {
  const MassSpringSettings s = sphere_settings();
  const std::vector<SpringQuad> quads = tissue_detail::make_spring_quads(s.springs);
  ASSERT_EQ(quads.size(), (s.springs.size() + 3) / 4);
  for (std::size_t e = 0; e < s.springs.size(); ++e) {
    EXPECT_EQ(quads[e / 4].i[e % 4], s.springs[e].i * sizeof(Padded3));
    EXPECT_EQ(quads[e / 4].j[e % 4], s.springs[e].j * sizeof(Padded3));
  }
  lanes_by_pair(quads, s);  // padding lanes are null springs
}

TEST(SpringLayout, IndexBeyondTheByteOffsetsIsAnError) {
  std::vector<Spring> springs{Spring{0, 1u << 27, 0.01, 1, 0}};
  EXPECT_THROW(tissue_detail::make_spring_quads(springs), Error);
  EXPECT_THROW(tissue_detail::make_spring_layout(springs, 2), Error);
}

}  // namespace
}  // namespace trocar
