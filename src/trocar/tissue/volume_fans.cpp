// The volume term's triangle pass in fans (volume_fans.h). On the shared liver 902 fans hold 82 %
// of the 4,384 triangles and the pass alone went from 4.6 to 3.1 ns per vertex (gallbladder 4.9
// → 3.1, abdominal wall 4.4 → 2.7; docs/tissue-integrators.md, "The AVX2 passes").
#include "trocar/tissue/volume_fans.h"

#include "trocar/tissue/avx2.h"

namespace trocar::tissue_detail {
namespace {

constexpr std::uint32_t kStride = sizeof(Padded3);

/// One fan, scalar: the same sums as the AVX2 kernel, coordinate by coordinate.
Real fan_scalar(const TriangleFan& f, const Padded3* x, const Padded3& origin, Padded3* g) {
  const Padded3& c = x[f.center / kStride];
  Real e[5][3];
  for (int k = 0; k < 5; ++k) {
    const Padded3& r = x[f.ring[k] / kStride];
    e[k][0] = r.x - c.x;
    e[k][1] = r.y - c.y;
    e[k][2] = r.z - c.z;
  }
  Real n[4][3];
  for (int k = 0; k < 4; ++k) {
    const Real* a = e[k];
    const Real* b = e[k + 1];
    n[k][0] = a[1] * b[2] - a[2] * b[1];
    n[k][1] = a[2] * b[0] - a[0] * b[2];
    n[k][2] = a[0] * b[1] - a[1] * b[0];
  }
  const auto add = [](Padded3& p, Real x0, Real x1, Real x2) {
    p.x += x0;
    p.y += x1;
    p.z += x2;
  };
  Real total[3];
  for (int a = 0; a < 3; ++a) total[a] = (n[0][a] + n[1][a]) + (n[2][a] + n[3][a]);
  add(g[f.center / kStride], total[0], total[1], total[2]);
  add(g[f.ring[0] / kStride], n[0][0], n[0][1], n[0][2]);
  for (int k = 1; k < 4; ++k)
    add(g[f.ring[k] / kStride], n[k - 1][0] + n[k][0], n[k - 1][1] + n[k][1], n[k - 1][2] + n[k][2]);
  add(g[f.ring[4] / kStride], n[3][0], n[3][1], n[3][2]);
  return (c.x - origin.x) * total[0] + (c.y - origin.y) * total[1] + (c.z - origin.z) * total[2];
}

Real single_scalar(const Triangle& tri, const Padded3* x, const Padded3& origin, Padded3* g) {
  const Padded3 &a = x[tri[0]], &b = x[tri[1]], &c = x[tri[2]];
  const Real e0 = b.x - a.x, e1 = b.y - a.y, e2 = b.z - a.z;
  const Real f0 = c.x - a.x, f1 = c.y - a.y, f2 = c.z - a.z;
  const Real n0 = e1 * f2 - e2 * f1, n1 = e2 * f0 - e0 * f2, n2 = e0 * f1 - e1 * f0;
  for (int k = 0; k < 3; ++k) {
    Padded3& gk = g[tri[k]];
    gk.x += n0;
    gk.y += n1;
    gk.z += n2;
  }
  return (a.x - origin.x) * n0 + (a.y - origin.y) * n1 + (a.z - origin.z) * n2;
}

#ifdef TROCAR_HAVE_X86
using namespace avx2;

TROCAR_AVX2 Real gradient_avx2(const VolumeLayout& layout, const Padded3* x, Padded3* g) {
  return volume_gradient(layout, PaddedLoad{x}, g);
}
#endif  // TROCAR_HAVE_X86

/// The triangles around `center` not yet placed, rotated to start at it: (center, p, q).
struct Corner {
  std::uint32_t p, q, triangle;
};

}  // namespace

VolumeLayout make_volume_layout(const std::vector<Triangle>& triangles, std::size_t vertex_count) {
  check_padded_vertex_count(vertex_count);
  VolumeLayout layout;
  if (triangles.empty()) return layout;
  layout.origin = triangles[0][0];
  std::vector<std::vector<std::uint32_t>> incident(vertex_count);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const std::uint32_t v : triangles[t]) incident[v].push_back(static_cast<std::uint32_t>(t));
  std::vector<std::uint8_t> placed(triangles.size(), 0);
  std::vector<Corner> corners;
  std::vector<std::uint8_t> visited;
  std::vector<std::uint32_t> run;
  // Greedy, vertex by vertex: chain the vertex's open triangles by their shared edges (one's q
  // is the next one's p) and cut each chain into runs of four. A vertex repeated in a triangle,
  // or an edge shared by more than two triangles, only ends a chain; whatever no fan takes is a
  // single triangle.
  for (std::uint32_t c = 0; c < vertex_count; ++c) {
    corners.clear();
    for (const std::uint32_t t : incident[c]) {
      if (placed[t]) continue;
      const Triangle& tri = triangles[t];
      const int at = tri[0] == c ? 0 : (tri[1] == c ? 1 : 2);
      const std::uint32_t p = tri[(at + 1) % 3], q = tri[(at + 2) % 3];
      if (p == c || q == c || p == q) continue;
      corners.push_back({p, q, t});
    }
    if (corners.size() < 4) continue;
    const std::size_t m = corners.size();
    // next[a] = the corner whose p is a's q (the first such), or m.
    const auto next_of = [&](std::size_t a) {
      for (std::size_t b = 0; b < m; ++b)
        if (b != a && corners[b].p == corners[a].q) return b;
      return m;
    };
    const auto has_previous = [&](std::size_t b) {
      for (std::size_t a = 0; a < m; ++a)
        if (a != b && corners[a].q == corners[b].p) return true;
      return false;
    };
    visited.assign(m, 0);
    const auto walk = [&](std::size_t start) {
      run.clear();
      for (std::size_t a = start; a < m && !visited[a]; a = next_of(a)) {
        visited[a] = 1;
        run.push_back(static_cast<std::uint32_t>(a));
        if (run.size() < 4) continue;
        TriangleFan& fan = layout.fans.emplace_back();
        fan.center = c * kStride;
        for (int k = 0; k < 4; ++k) {
          const Corner& corner = corners[run[static_cast<std::size_t>(k)]];
          fan.ring[k] = corner.p * kStride;
          placed[corner.triangle] = 1;
        }
        fan.ring[4] = corners[run[3]].q * kStride;
        run.clear();
      }
    };
    for (std::size_t a = 0; a < m; ++a)  // open chains from their first corner
      if (!visited[a] && !has_previous(a)) walk(a);
    for (std::size_t a = 0; a < m; ++a)  // closed rings from anywhere
      if (!visited[a]) walk(a);
  }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (!placed[t]) layout.singles.push_back(triangles[t]);
  return layout;
}

Real add_volume_gradient(const VolumeLayout& layout, const Padded3* x, Padded3* g, bool use_avx2) {
  if (layout.fans.empty() && layout.singles.empty()) return 0;
#ifdef TROCAR_HAVE_X86
  if (use_avx2) return gradient_avx2(layout, x, g);
#endif
  (void)use_avx2;
  const Padded3 origin = x[layout.origin];
  Real six_v = 0;
  for (const TriangleFan& f : layout.fans) six_v += fan_scalar(f, x, origin, g);
  for (const Triangle& tri : layout.singles) six_v += single_scalar(tri, x, origin, g);
  return six_v;
}

}  // namespace trocar::tissue_detail
