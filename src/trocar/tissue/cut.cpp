#include "trocar/tissue/cut.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace trocar {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

/// Open-addressing table from a sorted vertex pair to the first spring with that pair
/// (linear probing, Fibonacci hashing, load ≤ 1/2). Flat: one array, no node allocations.
class PairIndex {
 public:
  explicit PairIndex(std::size_t n) {
    std::size_t capacity = 16;
    int bits = 4;
    while (capacity < 2 * n) {
      capacity <<= 1;
      ++bits;
    }
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    shift_ = 64 - bits;
  }
  /// Keeps the first value given for a key. `key` must not be kEmpty (no vertex is 2³²−1).
  void insert(std::uint64_t key, std::uint32_t value) {
    for (std::size_t h = slot(key);; h = (h + 1) & mask_) {
      if (slots_[h].key == kEmpty) {
        slots_[h] = {key, value};
        return;
      }
      if (slots_[h].key == key) return;
    }
  }
  /// The value for `key`, kNone when absent.
  std::uint32_t find(std::uint64_t key) const {
    for (std::size_t h = slot(key);; h = (h + 1) & mask_) {
      if (slots_[h].key == key) return slots_[h].value;
      if (slots_[h].key == kEmpty) return kNone;
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::size_t slot(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  struct Slot {
    std::uint64_t key = kEmpty;
    std::uint32_t value = 0;
  };
  std::vector<Slot> slots_;  // key and value side by side: one cache line per probe
  std::size_t mask_ = 0;
  int shift_ = 60;
};

/// Union-find over a vertex's few triangles; the root of a set is its lowest element.
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a < b) parent[b] = a;
  else if (b < a) parent[a] = b;
}

/// Corner k of `tri` is the first occurrence of its vertex (a triangle counts once per vertex).
bool distinct_corner(const Triangle& tri, int k) {
  return k == 0 || (k == 1 && tri[1] != tri[0]) || (k == 2 && tri[2] != tri[0] && tri[2] != tri[1]);
}

/// Rule 4: the mass of one fan's copy of a vertex of a removed triangle; always > 0 and finite
/// with a finite inverse.
Real fan_mass(Real m_old, Real fan_share, Real all_share, std::size_t fans) {
  Real m;
  if (all_share > 0)
    m = fan_share > 0 ? m_old * (fan_share / all_share) : m_old * 1e-6;
  else
    m = m_old / static_cast<Real>(fans);
  constexpr Real kMin = std::numeric_limits<Real>::min();  // 1/kMin is finite
  if (!(m >= kMin) || !std::isfinite(m)) m = (m_old >= kMin && std::isfinite(m_old)) ? m_old : kMin;
  return m;
}

}  // namespace

CutTopology remove_triangles(const MassSpringSettings& settings, std::span<const std::uint32_t> removed) {
  const MassSpringSettings& s = settings;
  const std::size_t n_tris = s.triangles.size();
  const std::size_t n_verts = s.rest_positions.size();
  std::vector<std::uint8_t> gone(n_tris, 0);
  std::size_t n_gone = 0;
  for (std::uint32_t t : removed)
    if (t < n_tris && !gone[t]) {
      gone[t] = 1;
      ++n_gone;
    }

  CutTopology out;
  if (n_gone == 0) {  // rule 8: nothing to cut, the model as it is
    out.settings = s;
    out.vertex_origin.resize(n_verts);
    std::iota(out.vertex_origin.begin(), out.vertex_origin.end(), 0u);
    out.triangle_origin.resize(n_tris);
    std::iota(out.triangle_origin.begin(), out.triangle_origin.end(), 0u);
    out.spring_origin.resize(s.springs.size());
    std::iota(out.spring_origin.begin(), out.spring_origin.end(), 0u);
    return out;
  }
  MassSpringSettings& c = out.settings;
  c.mean_rest_area = s.mean_rest_area;  // rule 1
  c.closed = false;                     // rule 6
  c.rest_volume = s.rest_volume;
  c.k_area = s.k_area;                  // rule 7
  c.k_volume = s.k_volume;
  c.k_home = s.k_home;
  c.home_yield = s.home_yield;
  c.damping = s.damping;
  c.gravity = s.gravity;

  // The vertices of removed triangles ("touched"), in increasing order, and their slots.
  std::vector<std::uint32_t> touched_slot(n_verts, kNone);
  std::vector<std::uint32_t> touched;
  for (std::size_t t = 0; t < n_tris; ++t)
    if (gone[t])
      for (std::uint32_t v : s.triangles[t]) touched_slot[v] = 0;
  for (std::size_t v = 0; v < n_verts; ++v)
    if (touched_slot[v] == 0) {
      touched_slot[v] = static_cast<std::uint32_t>(touched.size());
      touched.push_back(static_cast<std::uint32_t>(v));
    }

  // Rules 1-2: kept triangles and the vertices they use, compacted in order.
  std::vector<std::uint32_t> new_vertex(n_verts, kNone);
  for (std::size_t t = 0; t < n_tris; ++t)
    if (!gone[t])
      for (std::uint32_t v : s.triangles[t]) new_vertex[v] = 0;
  for (std::size_t v = 0; v < n_verts; ++v)
    if (new_vertex[v] == 0) {
      new_vertex[v] = static_cast<std::uint32_t>(out.vertex_origin.size());
      out.vertex_origin.push_back(static_cast<std::uint32_t>(v));
    }
  const std::size_t n_kept_verts = out.vertex_origin.size();
  std::vector<std::uint32_t> new_triangle(n_tris, kNone);
  out.triangle_origin.reserve(n_tris - n_gone);
  c.triangles.reserve(n_tris - n_gone);
  c.rest_areas.reserve(n_tris - n_gone);
  for (std::size_t t = 0; t < n_tris; ++t) {
    if (gone[t]) continue;
    const Triangle& tri = s.triangles[t];
    new_triangle[t] = static_cast<std::uint32_t>(c.triangles.size());
    out.triangle_origin.push_back(static_cast<std::uint32_t>(t));
    c.triangles.push_back({new_vertex[tri[0]], new_vertex[tri[1]], new_vertex[tri[2]]});
    c.rest_areas.push_back(s.rest_areas[t]);
  }
  c.masses.resize(n_kept_verts);
  for (std::size_t i = 0; i < n_kept_verts; ++i) c.masses[i] = s.masses[out.vertex_origin[i]];

  // Each touched vertex's area share over all its old triangles (per corner, as build() lumps)
  // and its kept triangles (once each, increasing: CSR by counting).
  const std::size_t n_touched = touched.size();
  std::vector<Real> all_share(n_touched, 0.0);
  std::vector<std::uint32_t> kept_offsets(n_touched + 1, 0);
  for (std::size_t t = 0; t < n_tris; ++t) {
    const Triangle& tri = s.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t slot = touched_slot[tri[k]];
      if (slot == kNone) continue;
      all_share[slot] += s.rest_areas[t] / 3.0;
      if (!gone[t] && distinct_corner(tri, k)) ++kept_offsets[slot + 1];
    }
  }
  for (std::size_t i = 0; i < n_touched; ++i) kept_offsets[i + 1] += kept_offsets[i];
  std::vector<std::uint32_t> kept_tris(kept_offsets[n_touched]);
  {
    std::vector<std::uint32_t> fill(kept_offsets.begin(), kept_offsets.end() - 1);
    for (std::size_t t = 0; t < n_tris; ++t) {
      if (gone[t]) continue;
      const Triangle& tri = s.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t slot = touched_slot[tri[k]];
        if (slot != kNone && distinct_corner(tri, k)) kept_tris[fill[slot]++] = static_cast<std::uint32_t>(t);
      }
    }
  }

  // Rules 3-4: fans of each touched vertex (its kept triangles joined through the other vertex
  // of an edge they share), their masses, and a copy for every fan but the first.
  std::vector<std::uint32_t> parent;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> wings;  // (other vertex, local triangle)
  std::vector<Real> fan_share;
  std::vector<std::uint32_t> fan_vertex;
  for (std::size_t slot = 0; slot < n_touched; ++slot) {
    const std::uint32_t v = touched[slot];
    const std::uint32_t* tris = kept_tris.data() + kept_offsets[slot];
    const std::uint32_t n = kept_offsets[slot + 1] - kept_offsets[slot];
    if (n == 0) continue;  // dropped (rule 2)
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
    wings.clear();
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t w : s.triangles[tris[i]])
        if (w != v) wings.emplace_back(w, i);
    std::sort(wings.begin(), wings.end());
    for (std::size_t k = 1; k < wings.size(); ++k)
      if (wings[k].first == wings[k - 1].first) unite(parent, wings[k - 1].second, wings[k].second);
    fan_share.assign(n, 0.0);
    std::size_t fans = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t root = find_root(parent, i);
      if (root == i) ++fans;
      for (std::uint32_t u : s.triangles[tris[i]])
        if (u == v) fan_share[root] += s.rest_areas[tris[i]] / 3.0;
    }
    const Real m_old = s.masses[v];
    fan_vertex.assign(n, kNone);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (parent[i] != i) continue;  // roots after find_root: parent[i] == i only for roots
      const Real m = fan_mass(m_old, fan_share[i], all_share[slot], fans);
      if (i == 0) {  // the fan of the lowest kept triangle keeps the place
        fan_vertex[i] = new_vertex[v];
        c.masses[new_vertex[v]] = m;
      } else {
        fan_vertex[i] = static_cast<std::uint32_t>(out.vertex_origin.size());
        out.vertex_origin.push_back(v);
        c.masses.push_back(m);
      }
    }
    if (fans == 1) continue;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t copy = fan_vertex[find_root(parent, i)];
      if (copy == new_vertex[v]) continue;
      const Triangle& tri = s.triangles[tris[i]];
      Triangle& to = c.triangles[new_triangle[tris[i]]];
      for (int k = 0; k < 3; ++k)
        if (tri[k] == v) to[k] = copy;
    }
  }

  // Rule 4: per-vertex data through the origins.
  const std::size_t n_new = out.vertex_origin.size();
  c.rest_positions.resize(n_new);
  c.home_positions.resize(n_new);
  c.fixed.resize(n_new);
  c.inverse_masses.resize(n_new);
  for (std::size_t i = 0; i < n_new; ++i) {
    const std::uint32_t o = out.vertex_origin[i];
    c.rest_positions[i] = s.rest_positions[o];
    c.home_positions[i] = s.home_positions[o];
    c.fixed[i] = s.fixed[o];
    c.inverse_masses[i] = c.fixed[i] ? 0.0 : 1.0 / c.masses[i];
  }

  // Rule 5: the old springs by their sorted vertex pair, one table per kind.
  const std::size_t n_structural = std::min(s.structural_count, s.springs.size());
  PairIndex old_structural(n_structural);
  PairIndex old_bending(s.springs.size() - n_structural);
  for (std::size_t k = 0; k < s.springs.size(); ++k) {
    const Spring& p = s.springs[k];
    if (p.i >= n_verts || p.j >= n_verts) continue;  // not from build(): ignored
    (k < n_structural ? old_structural : old_bending).insert(pair_key(p.i, p.j), static_cast<std::uint32_t>(k));
  }

  // New edges in build()'s order, (v0, v1) increasing: vertex → triangles (CSR), then at each
  // vertex v its edges (v, w > v) with their triangles, sorted by (w, triangle).
  const std::size_t n_new_tris = c.triangles.size();
  std::vector<std::uint32_t> vt_offsets(n_new + 1, 0);
  for (const Triangle& tri : c.triangles)
    for (int k = 0; k < 3; ++k)
      if (distinct_corner(tri, k)) ++vt_offsets[tri[k] + 1];
  for (std::size_t v = 0; v < n_new; ++v) vt_offsets[v + 1] += vt_offsets[v];
  std::vector<std::uint32_t> vt(vt_offsets[n_new]);
  {
    std::vector<std::uint32_t> fill(vt_offsets.begin(), vt_offsets.end() - 1);
    for (std::size_t t = 0; t < n_new_tris; ++t)
      for (int k = 0; k < 3; ++k)
        if (distinct_corner(c.triangles[t], k)) vt[fill[c.triangles[t][k]]++] = static_cast<std::uint32_t>(t);
  }
  struct HalfEdge {
    std::uint32_t w;         // the edge's other (larger) vertex
    std::uint32_t t;         // the triangle
    std::uint32_t opposite;  // its corner opposite the edge
  };
  struct PendingBend {
    std::uint32_t a, b;  // new vertices, a < b
    std::uint32_t old;   // the old bending spring
  };
  std::vector<HalfEdge> half;
  std::vector<PendingBend> bending;  // after all structural springs (build()'s order)
  bending.reserve(s.springs.size() - n_structural);
  c.springs.reserve(s.springs.size());
  out.spring_origin.reserve(s.springs.size());
  for (std::uint32_t v = 0; v < n_new; ++v) {
    half.clear();
    for (std::uint32_t q = vt_offsets[v]; q < vt_offsets[v + 1]; ++q) {
      const Triangle& tri = c.triangles[vt[q]];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
        if (a == b || std::min(a, b) != v) continue;
        half.push_back({std::max(a, b), vt[q], tri[(k + 2) % 3]});
      }
    }
    std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
      return x.w != y.w ? x.w < y.w : x.t < y.t;
    });
    for (std::size_t first = 0; first < half.size();) {
      std::size_t last = first + 1;
      while (last < half.size() && half[last].w == half[first].w) ++last;
      const std::uint32_t w = half[first].w;
      const std::uint32_t old = old_structural.find(pair_key(out.vertex_origin[v], out.vertex_origin[w]));
      if (old != kNone) {
        const Spring& p = s.springs[old];
        c.springs.push_back({v, w, p.rest_length, p.stiffness, p.damping});
        out.spring_origin.push_back(old);
      }
      // Exactly two distinct triangles: each has the edge once, so its third corner is opposite.
      if (last - first == 2 && half[first].t != half[first + 1].t) {
        const std::uint32_t a = half[first].opposite, b = half[first + 1].opposite;
        if (a != b) {
          const std::uint32_t old_b = old_bending.find(pair_key(out.vertex_origin[a], out.vertex_origin[b]));
          if (old_b != kNone) bending.push_back({std::min(a, b), std::max(a, b), old_b});
        }
      }
      first = last;
    }
  }
  c.structural_count = c.springs.size();
  for (const PendingBend& q : bending) {
    const Spring& p = s.springs[q.old];
    c.springs.push_back({q.a, q.b, p.rest_length, p.stiffness, p.damping});
    out.spring_origin.push_back(q.old);
  }
  return out;
}

}  // namespace trocar
