#include "trocar/collision/ohc_broad_phase.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace trocar {
namespace {

// Cell coordinates are clamped to ±2^30 so that int32 arithmetic never overflows. Clamping is
// monotone, so two boxes that share a cell before clamping still do after, and the dedup rule
// (max of the lower cells) stays consistent; far-away boxes merely share boundary cells.
constexpr Real kCellClamp = 1073741824.0;

std::int32_t cell_of(Real x, Real inv_h) {
  const Real c = std::floor(x * inv_h);
  return static_cast<std::int32_t>(std::clamp(c, -kCellClamp, kCellClamp));
}

// Outcode of p against box [lo, hi]: bit 2k set when p[k] < lo[k], bit 2k+1 when p[k] > hi[k].
// A triangle's box misses the box iff some bit is set in all three corners' codes (all three
// corners beyond the same face), so c0 & c1 & c2 == 0 is exactly "the triangle's box overlaps".
std::uint8_t outcode(const Vec3& p, const Real lo[3], const Real hi[3]) {
  return static_cast<std::uint8_t>((p[0] < lo[0]) | ((p[0] > hi[0]) << 1) | ((p[1] < lo[1]) << 2) |
                                   ((p[1] > hi[1]) << 3) | ((p[2] < lo[2]) << 4) | ((p[2] > hi[2]) << 5));
}

}  // namespace

void OhcBroadPhase::find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) {
  out.clear();
  stats_ = {};
  const auto n = static_cast<std::uint32_t>(objects.size());
  primitives_.clear();
  if (n < 2) return;

  // 1. Object boxes and the tested, overlapping pairs.
  boxes_.resize(n);
  regions_.assign(n, Aabb{});
  tested_.assign(static_cast<std::size_t>(n) * n, 0);
  for (std::uint32_t i = 0; i < n; ++i) boxes_[i] = object_box(objects[i]);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (boxes_[i].is_empty()) continue;
    for (std::uint32_t j = i + 1; j < n; ++j) {
      if (boxes_[j].is_empty() || !roles_tested(objects[i].role, objects[j].role)) continue;
      if (!boxes_[i].overlaps(boxes_[j])) continue;
      tested_[static_cast<std::size_t>(i) * n + j] = 1;
      tested_[static_cast<std::size_t>(j) * n + i] = 1;
      ++stats_.objects_overlapping;
      if (settings_.cascade) {
        const Aabb overlap = boxes_[i].intersection(boxes_[j]);
        regions_[i].expand(overlap);
        regions_[j].expand(overlap);
      } else {
        regions_[i] = boxes_[i];
        regions_[j] = boxes_[j];
      }
    }
  }
  if (stats_.objects_overlapping == 0) return;

  // 2. The cascade: per object, the triangles whose (inflated) box touches its region, with
  //    their boxes clipped to it. Correctness: if triangles s of object i and t of object j
  //    intersect, a common point x lies in both inflated triangle boxes and so in both object
  //    boxes, hence in box_i ∩ box_j ⊆ region_i ∩ region_j: both pass and their clipped boxes
  //    still share x.
  Real edge_sum = 0;
  std::size_t edge_count = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Aabb& region = regions_[i];
    if (region.is_empty()) continue;
    const CollisionObject& object = objects[i];
    const Vec3* p = object.positions.data();
    const auto triangle_count = static_cast<std::uint32_t>(object.triangles.size());
    const Triangle* tris = object.triangles.data();
    // The triangle margin is at most kBoxMargin·(object size): test the raw corners against the
    // region grown by that much, then clip the inflated box (dropping the few that miss).
    const Aabb grown = region.inflated(kBoxMargin * boxes_[i].size().maxCoeff());
    const Real lo[3] = {grown.min.x(), grown.min.y(), grown.min.z()};
    const Real hi[3] = {grown.max.x(), grown.max.y(), grown.max.z()};
    outcodes_.resize(object.positions.size());
    std::uint8_t* codes = outcodes_.data();
    for (std::size_t v = 0; v < object.positions.size(); ++v) codes[v] = outcode(p[v], lo, hi);
    for (std::uint32_t t = 0; t < triangle_count; ++t) {
      const Triangle& tri = tris[t];
      if ((codes[tri[0]] & codes[tri[1]] & codes[tri[2]]) != 0) continue;
      const Vec3& a = p[tri[0]];
      const Vec3& b = p[tri[1]];
      const Vec3& c = p[tri[2]];
      const Aabb box = triangle_box(a, b, c).intersection(region);
      if (box.is_empty()) continue;
      Primitive prim;
      prim.min = box.min;
      prim.max = box.max;
      prim.object = i;
      prim.triangle = t;
      primitives_.push_back(prim);
      edge_sum += (b - a).norm() + (c - b).norm() + (a - c).norm();
      edge_count += 3;
    }
  }
  stats_.primitives_hashed = static_cast<std::uint32_t>(primitives_.size());
  if (primitives_.empty()) return;

  // 3. Cell size and cell ranges; double the cell while a few huge boxes would need too many.
  Real h = settings_.cell_size;
  if (!(h > 0) || !std::isfinite(h)) {
    h = settings_.auto_cell_factor * edge_sum / static_cast<Real>(edge_count);
  }
  if (!(h > 0) || !std::isfinite(h)) {
    Aabb all;
    for (std::uint32_t i = 0; i < n; ++i) all.expand(regions_[i]);
    h = all.is_empty() ? 1.0 : all.size().maxCoeff();
    if (!(h > 0) || !std::isfinite(h)) h = 1.0;
  }
  const Real budget = std::max<Real>(settings_.max_cells_per_primitive, 1.0) *
                          static_cast<Real>(primitives_.size()) + 64.0;
  std::uint64_t entry_count = 0;
  std::int32_t grid_lo[3];
  std::int32_t grid_hi[3];
  for (;;) {
    const Real inv_h = 1.0 / h;
    Real total = 0;
    for (int k = 0; k < 3; ++k) {
      grid_lo[k] = std::numeric_limits<std::int32_t>::max();
      grid_hi[k] = std::numeric_limits<std::int32_t>::min();
    }
    for (Primitive& prim : primitives_) {
      Real cells = 1;
      for (int k = 0; k < 3; ++k) {
        prim.lo[k] = cell_of(prim.min[k], inv_h);
        prim.hi[k] = cell_of(prim.max[k], inv_h);
        cells *= static_cast<Real>(prim.hi[k] - prim.lo[k]) + 1;
        grid_lo[k] = std::min(grid_lo[k], prim.lo[k]);
        grid_hi[k] = std::max(grid_hi[k], prim.hi[k]);
      }
      total += cells;
    }
    if (total <= budget || !std::isfinite(h * 2)) {
      entry_count = static_cast<std::uint64_t>(total);
      break;
    }
    h *= 2;
  }
  stats_.cell_size = h;
  stats_.entries = entry_count;

  // 4. Counting sort of the entries by slot. The table only grows (power of two ≥ 2·entries).
  const std::size_t needed = std::bit_ceil(std::max<std::size_t>(16, 2 * static_cast<std::size_t>(entry_count)));
  if (slot_start_.size() < needed + 1) slot_start_.resize(needed + 1);
  const std::size_t table = slot_start_.size() - 1;
  const auto mask = static_cast<std::uint32_t>(table - 1);
  stats_.table_size = static_cast<std::uint32_t>(table);
  std::uint32_t* start = slot_start_.data();
  std::fill(start, start + table + 1, 0u);
  for (const Primitive& prim : primitives_) {
    for (std::int32_t z = prim.lo[2]; z <= prim.hi[2]; ++z)
      for (std::int32_t y = prim.lo[1]; y <= prim.hi[1]; ++y)
        for (std::int32_t x = prim.lo[0]; x <= prim.hi[0]; ++x) ++start[cell_hash(x, y, z) & mask];
  }
  // Inclusive prefix sum: start[s] = end of slot s. Filling from the back turns it into the
  // beginning of slot s, and start[s + 1] (table: = entry_count) is its end.
  std::uint32_t running = 0;
  for (std::size_t s = 0; s < table; ++s) {
    running += start[s];
    start[s] = running;
  }
  start[table] = running;
  entries_.resize(entry_count);
  Entry* entries = entries_.data();
  for (std::uint32_t k = 0; k < primitives_.size(); ++k) {
    const Primitive& prim = primitives_[k];
    for (std::int32_t z = prim.lo[2]; z <= prim.hi[2]; ++z)
      for (std::int32_t y = prim.lo[1]; y <= prim.hi[1]; ++y)
        for (std::int32_t x = prim.lo[0]; x <= prim.hi[0]; ++x)
          entries[--start[cell_hash(x, y, z) & mask]] = {x, y, z, k};
  }

  // 5. Per slot: sort by (cell, primitive) so hash collisions fall apart into cells, then
  //    classify each cell and emit pairs from the potential-colliding ones.
  const auto entry_less = [](const Entry& a, const Entry& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    if (a.z != b.z) return a.z < b.z;
    return a.primitive < b.primitive;
  };
  for (std::size_t s = 0; s < table; ++s) {
    const std::uint32_t b = start[s];
    const std::uint32_t e = start[s + 1];
    if (e == b) continue;
    if (e - b == 1) {
      ++stats_.cells_touched;
      ++stats_.solo_cells;
      continue;
    }
    if (e - b <= 16) {
      for (std::uint32_t i = b + 1; i < e; ++i) {  // insertion sort: slots are tiny
        const Entry v = entries[i];
        std::uint32_t j = i;
        for (; j > b && entry_less(v, entries[j - 1]); --j) entries[j] = entries[j - 1];
        entries[j] = v;
      }
    } else {
      std::sort(entries + b, entries + e, entry_less);
    }
    for (std::uint32_t r = b; r < e;) {
      std::uint32_t r_end = r + 1;
      while (r_end < e && entries[r_end].x == entries[r].x && entries[r_end].y == entries[r].y &&
             entries[r_end].z == entries[r].z)
        ++r_end;
      ++stats_.cells_touched;
      // Primitives were appended object by object, so the run is sorted by object too.
      if (primitives_[entries[r].primitive].object == primitives_[entries[r_end - 1].primitive].object) {
        ++stats_.solo_cells;
      } else {
        ++stats_.potential_cells;
        emit_cell_pairs(std::span<const Entry>(entries + r, r_end - r), objects, out);
      }
      r = r_end;
    }
  }
  std::uint64_t block = 1;
  for (int k = 0; k < 3; ++k) block *= static_cast<std::uint64_t>(static_cast<std::int64_t>(grid_hi[k]) - grid_lo[k] + 1);
  stats_.empty_cells = block - stats_.cells_touched;
  stats_.candidate_pairs = out.size();
}

void OhcBroadPhase::emit_cell_pairs(std::span<const Entry> cell, std::span<const CollisionObject> objects,
                                    std::vector<CandidatePair>& out) {
  const auto n = static_cast<std::uint32_t>(objects.size());
  const std::int32_t cx = cell[0].x;
  const std::int32_t cy = cell[0].y;
  const std::int32_t cz = cell[0].z;
  // The cell is sorted by primitive and so by object: pair each primitive only with those of
  // later objects (skipping its own object's group).
  std::size_t group_end = 0;
  for (std::size_t i = 0; i < cell.size(); ++i) {
    const Primitive& a = primitives_[cell[i].primitive];
    if (i >= group_end) {
      group_end = i + 1;
      while (group_end < cell.size() && primitives_[cell[group_end].primitive].object == a.object) ++group_end;
    }
    for (std::size_t j = group_end; j < cell.size(); ++j) {
      const Primitive& b = primitives_[cell[j].primitive];
      // Emit only from the cell holding the minimum corner of the boxes' overlap: per axis the
      // larger of the two first cells (floor is monotone, so this is the cell of max(min_a, min_b)).
      if (std::max(a.lo[0], b.lo[0]) != cx || std::max(a.lo[1], b.lo[1]) != cy ||
          std::max(a.lo[2], b.lo[2]) != cz)
        continue;
      if (a.min[0] > b.max[0] || b.min[0] > a.max[0] || a.min[1] > b.max[1] || b.min[1] > a.max[1] ||
          a.min[2] > b.max[2] || b.min[2] > a.max[2])
        continue;
      if (!tested_[static_cast<std::size_t>(a.object) * n + b.object]) continue;
      if (object_first(objects[a.object].role, a.object, objects[b.object].role, b.object)) {
        out.push_back({a.object, b.object, a.triangle, b.triangle});
      } else {
        out.push_back({b.object, a.object, b.triangle, a.triangle});
      }
    }
  }
}

}  // namespace trocar
