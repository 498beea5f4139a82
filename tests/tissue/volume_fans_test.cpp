// The volume pass in fans (volume_fans.h): every triangle is used exactly once, as one of a
// fan's four (a cyclic rotation of it, around a shared vertex, consecutive through shared edges)
// or alone; the gradient Σ_{t∋i} n_t and 6V of both paths agree with a per-triangle sum written
// here; broken meshes (a repeated vertex, an edge of three triangles, a vertex of valence four
// whose fan closes on itself) still give the right sums.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <random>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/tissue/volume_fans.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

using tissue_detail::Padded3;
using tissue_detail::TriangleFan;
using tissue_detail::VolumeLayout;

constexpr std::uint32_t kStride = sizeof(Padded3);

/// Triangle as the sorted rotation key (smallest index first, orientation kept).
Triangle canonical(Triangle t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

/// How often each mesh triangle (by its canonical rotation) appears in the layout; also checks
/// that each fan's triangles are consecutive around its center.
std::map<Triangle, int> uses(const VolumeLayout& layout) {
  std::map<Triangle, int> count;
  for (const TriangleFan& f : layout.fans) {
    EXPECT_EQ(f.center % kStride, 0u);
    for (int k = 0; k < 4; ++k)
      ++count[canonical({f.center / kStride, f.ring[k] / kStride, f.ring[k + 1] / kStride})];
  }
  for (const Triangle& t : layout.singles) ++count[canonical(t)];
  return count;
}

void expect_each_triangle_once(const TriMesh& mesh, const VolumeLayout& layout) {
  std::map<Triangle, int> expected;
  for (const Triangle& t : mesh.triangles) ++expected[canonical(t)];
  EXPECT_EQ(uses(layout), expected);
  EXPECT_EQ(layout.fans.size() * 4 + layout.singles.size(), mesh.triangles.size());
}

/// Reference: g_i = Σ_{t∋i} (b − a) × (c − a), 6V = Σ_t (a − o)·n_t, o = first triangle's first
/// vertex; and the scales rounding is relative to, with s_t = |b − a| |c − a|: max_i Σ_{t∋i} s_t
/// and Σ_t max_k |x_k − o| s_t (the terms cancel on an open, odd or random mesh, so the sums
/// alone can be 0).
struct Reference {
  std::vector<Vec3> gradient;
  Real six_volume = 0;
  Real gradient_scale = 0, volume_scale = 0;
};
Reference reference(const TriMesh& mesh) {
  Reference r;
  r.gradient.assign(mesh.vertex_count(), Vec3::Zero());
  std::vector<Real> magnitude(mesh.vertex_count(), 0);
  const Vec3 o = mesh.positions[mesh.triangles[0][0]];
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    // The size of the cross product's terms: a fused multiply-subtract leaves rounding of that
    // size even where n is 0 (b = c).
    const Real terms = (b - a).norm() * (c - a).norm();
    for (const std::uint32_t v : t) {
      r.gradient[v] += n;
      magnitude[v] += terms;
    }
    r.six_volume += (a - o).dot(n);
    // A fan takes (c − o)·n_t about another corner c of t: equal, to rounding at that corner's scale.
    r.volume_scale += std::max({(a - o).norm(), (b - o).norm(), (c - o).norm()}) * terms;
  }
  for (const Real m : magnitude) r.gradient_scale = std::max(r.gradient_scale, m);
  return r;
}

/// Both paths against the reference, to rounding.
void expect_sums_match(const TriMesh& mesh, const VolumeLayout& layout) {
  const Reference ref = reference(mesh);
  tissue_detail::PaddedArrays arrays;
  arrays.allocate(mesh.vertex_count(), 2);
  std::span<Padded3> x = arrays[0];
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
    x[i] = Padded3{mesh.positions[i].x(), mesh.positions[i].y(), mesh.positions[i].z(), 0};
  for (bool simd : {true, false}) {
    std::span<Padded3> g = arrays[1];
    std::fill(g.begin(), g.end(), Padded3{});
    const Real six_v = tissue_detail::add_volume_gradient(layout, x.data(), g.data(), simd);
    EXPECT_NEAR(six_v, ref.six_volume, 1e-14 * ref.volume_scale) << "simd " << simd;
    Real worst = 0;
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
      worst = std::max(worst, (Vec3(g[i].x, g[i].y, g[i].z) - ref.gradient[i]).norm());
      EXPECT_EQ(g[i].w, 0.0);
    }
    EXPECT_LE(worst, 1e-14 * ref.gradient_scale) << "simd " << simd;
  }
}

TEST(VolumeFans, IcosphereEveryTriangleOnceMostInFansSumsMatch) {
  TriMesh mesh = make_icosphere(0.03, 3);
  for (Vec3& p : mesh.positions) p += Vec3(0.2, -0.1, 0.05);  // away from the origin
  const VolumeLayout layout = tissue_detail::make_volume_layout(mesh.triangles, mesh.vertex_count());
  expect_each_triangle_once(mesh, layout);
  EXPECT_GE(layout.fans.size() * 4, mesh.triangles.size() * 3 / 4);  // measured: 257 fans, 1028 of 1280
  expect_sums_match(mesh, layout);
  // A closed sphere: 6V = 6 × volume, the gradient sums to zero.
  const Reference ref = reference(mesh);
  EXPECT_NEAR(ref.six_volume / 6, 4.0 / 3.0 * 3.14159265358979 * 0.03 * 0.03 * 0.03, 2e-6);
}

TEST(VolumeFans, OctahedronFanClosesOnItself) {
  // Every vertex has valence four: the first fan around vertex 0 is its whole ring, so its first
  // and last ring vertex are the same and get two writes.
  TriMesh mesh;
  mesh.positions = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const VolumeLayout layout = tissue_detail::make_volume_layout(mesh.triangles, mesh.vertex_count());
  expect_each_triangle_once(mesh, layout);
  ASSERT_GE(layout.fans.size(), 1u);
  EXPECT_EQ(layout.fans[0].ring[0], layout.fans[0].ring[4]);
  expect_sums_match(mesh, layout);
  EXPECT_NEAR(reference(mesh).six_volume, 6 * 4.0 / 3.0, 1e-12);  // |x|+|y|+|z| ≤ 1: volume 4/3
}

TEST(VolumeFans, BrokenMeshesKeepEveryTriangleOnce) {
  // A fan of five triangles around vertex 0, a sixth on one of its edges (an edge of three
  // triangles), a triangle with a repeated vertex, and a lone triangle.
  TriMesh mesh;
  mesh.positions = {Vec3(0, 0, 0.1), Vec3(1, 0, 0), Vec3(0.5, 0.8, 0), Vec3(-0.5, 0.8, 0),
                    Vec3(-1, 0, 0),  Vec3(-0.5, -0.8, 0), Vec3(0.5, -0.8, 0.2), Vec3(3, 3, 3), Vec3(4, 3, 3),
                    Vec3(3, 4, 3)};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 2, 6},
                    {1, 1, 2}, {7, 8, 9}};
  const VolumeLayout layout = tissue_detail::make_volume_layout(mesh.triangles, mesh.vertex_count());
  expect_each_triangle_once(mesh, layout);
  EXPECT_GE(layout.fans.size(), 1u);
  expect_sums_match(mesh, layout);
}

TEST(VolumeFans, RandomTriangleSoupsKeepEveryTriangleOnce) {
  // Few vertices, many triangles: repeated triangles, both orientations, edges of many
  // triangles, repeated vertices within a triangle.
  std::mt19937 engine(2026);
  const auto rng = [&] { return static_cast<std::uint32_t>(engine()); };
  std::size_t fans = 0;
  for (int trial = 0; trial < 200; ++trial) {
    TriMesh mesh;
    const std::uint32_t nv = 3 + rng() % 10;
    std::uniform_real_distribution<Real> u(-1, 1);
    for (std::uint32_t v = 0; v < nv; ++v) mesh.positions.emplace_back(u(engine), u(engine), u(engine));
    const std::size_t nt = 1 + rng() % 40;
    for (std::size_t t = 0; t < nt; ++t) mesh.triangles.push_back({rng() % nv, rng() % nv, rng() % nv});
    const VolumeLayout layout = tissue_detail::make_volume_layout(mesh.triangles, mesh.vertex_count());
    fans += layout.fans.size();
    expect_each_triangle_once(mesh, layout);
    expect_sums_match(mesh, layout);
    if (HasFailure()) {
      ADD_FAILURE() << "trial " << trial;
      return;
    }
  }
  EXPECT_GT(fans, 50u);  // the soups do make fans (measured: 116 over the 200 trials)
}

TEST(VolumeFans, SharedLiverMostlyFansSumsMatch) {
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.obj");
  const TriMesh mesh = load_mesh(path);
  const VolumeLayout layout = tissue_detail::make_volume_layout(mesh.triangles, mesh.vertex_count());
  expect_each_triangle_once(mesh, layout);
  // Measured: 902 fans hold 3608 of the 4384 triangles (82 %).
  EXPECT_GE(layout.fans.size() * 4, mesh.triangles.size() * 8 / 10);
  expect_sums_match(mesh, layout);
}

TEST(VolumeFans, EmptyAndTooLarge) {
  const VolumeLayout empty = tissue_detail::make_volume_layout({}, 0);
  EXPECT_EQ(tissue_detail::add_volume_gradient(empty, nullptr, nullptr, true), 0.0);
  EXPECT_THROW(tissue_detail::make_volume_layout({}, std::size_t{1} << 27), Error);
}

}  // namespace
}  // namespace trocar
