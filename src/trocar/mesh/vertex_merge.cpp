// vertex_representatives(): exact merge by sorting, tolerance merge by a spatial hash grid.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "trocar/mesh/repair.h"

namespace trocar {
namespace {

bool finite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

// Exact: sort the indices by (x, y, z, index); the first of each run of equal positions is
// the run's lowest index and becomes everyone's representative. O(V log V).
std::vector<std::uint32_t> exact_representatives(const std::vector<Vec3>& positions) {
  const std::size_t n = positions.size();
  std::vector<std::uint32_t> rep(n), order;
  std::iota(rep.begin(), rep.end(), 0u);
  order.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    if (finite(positions[i])) order.push_back(i);
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3& p = positions[a];
    const Vec3& q = positions[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1; i < order.size(); ++i) {
    const std::uint32_t prev = order[i - 1], cur = order[i];
    if (positions[prev] == positions[cur]) rep[cur] = rep[prev];
  }
  return rep;
}

// Tolerance: grid of cell size = tolerance, vertices visited in index order. A vertex looks
// through the 27 cells around its own for representatives within the tolerance and maps to
// the lowest-index one; with none it becomes a representative and is filed in its cell.
// Cells hold singly linked lists in one flat `next` array (no per-cell allocation beyond the
// hash map's nodes). Expected O(V) for bounded density.
std::vector<std::uint32_t> grid_representatives(const std::vector<Vec3>& positions, Real tolerance) {
  constexpr std::uint32_t kEnd = 0xffffffffu;
  const std::size_t n = positions.size();
  std::vector<std::uint32_t> rep(n), next(n, kEnd);
  std::iota(rep.begin(), rep.end(), 0u);
  const Real inv = 1.0 / tolerance;
  const Real tol2 = tolerance * tolerance;
  auto cell_key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    // 21 bits per axis after wrapping; collisions only cost extra distance checks.
    const auto u = [](std::int64_t c) { return static_cast<std::uint64_t>(c) & 0x1fffffu; };
    return (u(x) << 42) | (u(y) << 21) | u(z);
  };
  std::unordered_map<std::uint64_t, std::uint32_t> head;
  head.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3& p = positions[i];
    if (!finite(p)) continue;
    const auto cx = static_cast<std::int64_t>(std::floor(p.x() * inv));
    const auto cy = static_cast<std::int64_t>(std::floor(p.y() * inv));
    const auto cz = static_cast<std::int64_t>(std::floor(p.z() * inv));
    std::uint32_t best = kEnd;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = head.find(cell_key(cx + dx, cy + dy, cz + dz));
          if (it == head.end()) continue;
          for (std::uint32_t j = it->second; j != kEnd; j = next[j])
            if (j < best && (positions[j] - p).squaredNorm() <= tol2) best = j;
        }
    if (best != kEnd) {
      rep[i] = best;
    } else {
      auto [it, inserted] = head.try_emplace(cell_key(cx, cy, cz), i);
      if (!inserted) {
        next[i] = it->second;
        it->second = i;
      }
    }
  }
  return rep;
}

}  // namespace

std::vector<std::uint32_t> vertex_representatives(const std::vector<Vec3>& positions, Real tolerance) {
  if (!(tolerance > 0) || !std::isfinite(tolerance)) return exact_representatives(positions);
  // Grid coordinates must fit an int64; a tolerance that small is an exact merge in effect.
  Real max_abs = 0;
  for (const Vec3& p : positions)
    if (finite(p)) max_abs = std::max(max_abs, p.cwiseAbs().maxCoeff());
  if (max_abs / tolerance > 1e15) return exact_representatives(positions);
  return grid_representatives(positions, tolerance);
}

}  // namespace trocar
