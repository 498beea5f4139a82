#pragma once
/// A uniform spatial hash of triangle boxes, rebuilt every step without allocating once warm
/// (the broad phase of the tissue–tissue contact; docs/response.md, "Tissue against tissue").
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// Triangles binned by the cells their (expanded) boxes overlap. Cells are hashed into a fixed
/// table of buckets (Teschner et al. 2003, "Optimized spatial hashing for collision detection of
/// deformable objects"): a query sees every triangle whose box overlaps its box, and possibly a
/// few more that share a bucket (the narrow phase rejects those).
class TriangleGrid {
 public:
  /// Sizes the table for `triangle_count` triangles with cells of edge `cell_size` (m, > 0).
  void reset(std::size_t triangle_count, Real cell_size);
  /// Bins triangle t's box [lo[t], hi[t]] for t < lo.size(). Allocates only when more
  /// (triangle, cell) entries are needed than any earlier build held.
  void build(std::span<const Vec3> lo, std::span<const Vec3> hi);
  /// Calls visit(t) once for every binned triangle whose bucket a cell of [lo, hi] falls in
  /// (each triangle at most once per query).
  template <class Visit>
  void query(const Vec3& lo, const Vec3& hi, Visit&& visit);

  Real cell_size() const { return cell_; }

 private:
  struct CellRange {
    std::int64_t x0, y0, z0, x1, y1, z1;
  };
  CellRange range(const Vec3& lo, const Vec3& hi) const;
  std::uint32_t bucket(std::int64_t x, std::int64_t y, std::int64_t z) const;

  Real cell_ = 1;
  Real inverse_cell_ = 1;
  std::uint32_t mask_ = 0;                 ///< bucket count − 1 (a power of two)
  std::vector<std::uint32_t> start_;       ///< per bucket + 1: offsets into entries_
  std::vector<std::uint32_t> entries_;     ///< triangle indices, grouped by bucket
  std::vector<std::uint32_t> stamp_;       ///< per triangle: the query that last saw it
  std::uint32_t query_ = 0;
};

template <class Visit>
void TriangleGrid::query(const Vec3& lo, const Vec3& hi, Visit&& visit) {
  if (++query_ == 0) {  // the stamps wrapped: forget them all
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    query_ = 1;
  }
  const CellRange r = range(lo, hi);
  for (std::int64_t z = r.z0; z <= r.z1; ++z)
    for (std::int64_t y = r.y0; y <= r.y1; ++y)
      for (std::int64_t x = r.x0; x <= r.x1; ++x) {
        const std::uint32_t b = bucket(x, y, z);
        for (std::uint32_t e = start_[b]; e < start_[b + 1]; ++e) {
          const std::uint32_t t = entries_[e];
          if (stamp_[t] == query_) continue;
          stamp_[t] = query_;
          visit(t);
        }
      }
}

}  // namespace trocar
