#include "trocar/response/triangle_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace trocar {
namespace {

/// A box wider than this many cells per axis is clamped to it (a torn-apart tissue must not
/// make the build quadratic); its triangle is then found through the clamped cells only.
constexpr std::int64_t kMaxCellsPerAxis = 64;

std::int64_t cell_of(Real x, Real inverse_cell) {
  const Real c = std::floor(x * inverse_cell);
  // Non-finite or absurd coordinates land in one far cell instead of overflowing.
  if (!(std::abs(c) < 1e15)) return 0;
  return static_cast<std::int64_t>(c);
}

}  // namespace

void TriangleGrid::reset(std::size_t triangle_count, Real cell_size) {
  cell_ = cell_size;
  inverse_cell_ = 1 / cell_size;
  const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(64, 2 * triangle_count));
  mask_ = static_cast<std::uint32_t>(buckets - 1);
  start_.assign(buckets + 1, 0);
  entries_.clear();
  entries_.reserve(27 * triangle_count);  // a box over 3 cells on every axis, each triangle
  stamp_.assign(triangle_count, 0);
  query_ = 0;
}

TriangleGrid::CellRange TriangleGrid::range(const Vec3& lo, const Vec3& hi) const {
  CellRange r{cell_of(lo.x(), inverse_cell_), cell_of(lo.y(), inverse_cell_), cell_of(lo.z(), inverse_cell_),
              cell_of(hi.x(), inverse_cell_), cell_of(hi.y(), inverse_cell_), cell_of(hi.z(), inverse_cell_)};
  r.x1 = std::clamp(r.x1, r.x0, r.x0 + kMaxCellsPerAxis - 1);
  r.y1 = std::clamp(r.y1, r.y0, r.y0 + kMaxCellsPerAxis - 1);
  r.z1 = std::clamp(r.z1, r.z0, r.z0 + kMaxCellsPerAxis - 1);
  return r;
}

std::uint32_t TriangleGrid::bucket(std::int64_t x, std::int64_t y, std::int64_t z) const {
  // The three large primes of Teschner et al. 2003.
  const std::uint64_t h = (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
                          (static_cast<std::uint64_t>(z) * 83492791u);
  return static_cast<std::uint32_t>(h) & mask_;
}

void TriangleGrid::build(std::span<const Vec3> lo, std::span<const Vec3> hi) {
  // Counting sort by bucket: count, prefix sums, fill (start_[b] runs back to the bucket's start).
  std::fill(start_.begin(), start_.end(), 0u);
  std::size_t total = 0;
  for (std::size_t t = 0; t < lo.size(); ++t) {
    const CellRange r = range(lo[t], hi[t]);
    for (std::int64_t z = r.z0; z <= r.z1; ++z)
      for (std::int64_t y = r.y0; y <= r.y1; ++y)
        for (std::int64_t x = r.x0; x <= r.x1; ++x) {
          ++start_[bucket(x, y, z) + 1];
          ++total;
        }
  }
  for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
  // Grown with room to spare: boxes that swell a little each step must not reallocate each step.
  if (entries_.size() < total) entries_.resize(std::max(total, 2 * entries_.size()));
  for (std::size_t t = 0; t < lo.size(); ++t) {
    const CellRange r = range(lo[t], hi[t]);
    for (std::int64_t z = r.z0; z <= r.z1; ++z)
      for (std::int64_t y = r.y0; y <= r.y1; ++y)
        for (std::int64_t x = r.x0; x <= r.x1; ++x) entries_[start_[bucket(x, y, z)]++] = static_cast<std::uint32_t>(t);
  }
  // Each start_[b] now holds the end of bucket b, i.e. the start of b + 1: shift back by one.
  for (std::size_t b = start_.size() - 1; b > 0; --b) start_[b] = start_[b - 1];
  start_[0] = 0;
}

}  // namespace trocar
