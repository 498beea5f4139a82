#include "trocar/collision/ohc_broad_phase.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "trocar/collision/ohc_kernels.h"
#include "trocar/core/cpu_features.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace trocar {
namespace {

// Cell coordinates are clamped to ±2^30 so that int32 arithmetic never overflows. Clamping is
// monotone, so two boxes that share a cell before clamping still do after, and the dedup rule
// (max of the lower cells) stays consistent; far-away boxes merely share boundary cells.
constexpr Real kCellClamp = 1073741824.0;

[[maybe_unused]] std::int32_t cell_of(Real x, Real inv_h) {  // the portable cell_range()
  // floor(clamp(v)) = clamp(floor(v)) as the bounds are integers. The floor is a truncation
  // stepped down for negative non-integers (exact for |v| ≤ 2^30; no libm call, which the
  // baseline x86-64 ISA would need). NaN gives INT32_MIN, as the cast in a plain floor would.
  const Real v = std::clamp(x * inv_h, -kCellClamp, kCellClamp);
  if (!(v == v)) return std::numeric_limits<std::int32_t>::min();
  const auto t = static_cast<std::int32_t>(v);
  return static_cast<Real>(t) > v ? t - 1 : t;
}

// True when the box of triangle abc (not inflated) misses the box [g_lo, g_hi] on some axis.
// SSE2: x and y in one register, z in another. std::min(u, v) is (v < u ? v : u), which is
// _mm_min_pd(v, u) (and std::max likewise), so the result is the scalar test's, NaN included.
bool raw_box_outside(const Vec3& a, const Vec3& b, const Vec3& c, const Real (&g_lo)[3], const Real (&g_hi)[3]) {
#if defined(__SSE2__)
  const __m128d a_xy = _mm_loadu_pd(a.data());
  const __m128d b_xy = _mm_loadu_pd(b.data());
  const __m128d c_xy = _mm_loadu_pd(c.data());
  const __m128d a_z = _mm_load_sd(a.data() + 2);
  const __m128d b_z = _mm_load_sd(b.data() + 2);
  const __m128d c_z = _mm_load_sd(c.data() + 2);
  const __m128d lo_xy = _mm_min_pd(c_xy, _mm_min_pd(b_xy, a_xy));
  const __m128d hi_xy = _mm_max_pd(c_xy, _mm_max_pd(b_xy, a_xy));
  const __m128d lo_z = _mm_min_sd(c_z, _mm_min_sd(b_z, a_z));
  const __m128d hi_z = _mm_max_sd(c_z, _mm_max_sd(b_z, a_z));
  const __m128d out_xy = _mm_or_pd(_mm_cmplt_pd(hi_xy, _mm_loadu_pd(g_lo)), _mm_cmpgt_pd(lo_xy, _mm_loadu_pd(g_hi)));
  const __m128d out_z = _mm_or_pd(_mm_cmplt_sd(hi_z, _mm_load_sd(g_lo + 2)), _mm_cmpgt_sd(lo_z, _mm_load_sd(g_hi + 2)));
  return (_mm_movemask_pd(out_xy) | (_mm_movemask_pd(out_z) & 1)) != 0;
#else
  bool outside = false;
  for (int axis = 0; axis < 3; ++axis) {
    const Real lo = std::min(std::min(a[axis], b[axis]), c[axis]);
    const Real hi = std::max(std::max(a[axis], b[axis]), c[axis]);
    outside |= hi < g_lo[axis] || lo > g_hi[axis];
  }
  return outside;
#endif
}

// The portable opening of triangles [begin, end) (in cluster order: ordered[o] its vertices,
// order[o] its id) of one object: those whose raw box touches [g_lo, g_hi] and whose inflated
// box clipped to `clip` is not empty get their box and extents written at out[opened…] and
// set_id(opened, triangle) called; returns the new end. What open_cluster_avx512 does eight at
// a time.
template <class SetId>
std::uint32_t open_cluster_portable(const Vec3* p, const Triangle* ordered, const std::uint32_t* order,
                                    std::uint32_t begin, std::uint32_t end, const Aabb& clip,
                                    const Real (&g_lo)[3], const Real (&g_hi)[3],
                                    const ohc_detail::OpenedArrays& out, std::uint32_t opened, SetId set_id) {
  for (std::uint32_t o = begin; o < end; ++o) {
    const Triangle& tri = ordered[o];
    const Vec3& a = p[tri[0]];
    const Vec3& b = p[tri[1]];
    const Vec3& cc = p[tri[2]];
    // Quick rejection on the raw (uninflated) box against the grown region, which holds
    // every triangle margin: most triangles of an opened cluster stop here.
    if (raw_box_outside(a, b, cc, g_lo, g_hi)) continue;
    const Aabb box = triangle_box(a, b, cc).intersection(clip);
    if (box.is_empty()) continue;
    for (int axis = 0; axis < 3; ++axis) {
      out.lo[axis][opened] = box.min[axis];
      out.hi[axis][opened] = box.max[axis];
    }
    Real d_lo[ohc_detail::kDopAxes];
    Real d_hi[ohc_detail::kDopAxes];
    ohc_detail::dop_extents(a, b, cc, d_lo, d_hi);
    for (int d = 0; d < ohc_detail::kDopAxes; ++d) {
      out.dop_lo[d][opened] = d_lo[d];
      out.dop_hi[d][opened] = d_hi[d];
    }
    set_id(opened++, order[o]);
  }
  return opened;
}

// Up to this many (cluster of one object, cluster of the other) pairs the cluster cascade tests
// them all instead of sorting the clusters for a sweep.
constexpr std::size_t kAllPairsClusters = 1024;

// Spreads the low 21 bits of x to every third bit (Morton code helper).
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// Inclusive prefix sum of start[0, count) in place (start[s] becomes the end of slot s); returns
// the total. count is a power of two ≥ 16.
std::uint32_t inclusive_prefix_sum(std::uint32_t* start, std::size_t count) {
#if defined(__SSE2__)
  // Four slots at a time: a prefix sum within the register by two shifted adds, plus the running
  // total; the scalar loop is one long chain of dependent adds.
  __m128i carry = _mm_setzero_si128();
  for (std::size_t s = 0; s < count; s += 4) {
    __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(start + s));
    x = _mm_add_epi32(x, _mm_slli_si128(x, 4));
    x = _mm_add_epi32(x, _mm_slli_si128(x, 8));
    x = _mm_add_epi32(x, carry);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(start + s), x);
    carry = _mm_shuffle_epi32(x, _MM_SHUFFLE(3, 3, 3, 3));
  }
  return start[count - 1];
#else
  std::uint32_t running = 0;
  for (std::size_t s = 0; s < count; ++s) {
    running += start[s];
    start[s] = running;
  }
  return running;
#endif
}

}  // namespace

void OhcBroadPhase::build_clusters(ObjectClusters& c, const CollisionObject& object) {
  c.triangles = object.triangles.data();
  c.triangle_count = object.triangles.size();
  c.vertex_count = object.positions.size();
  const auto n = static_cast<std::uint32_t>(object.triangles.size());
  if (object.positions.size() > std::numeric_limits<std::uint32_t>::max() / 3) {
    throw std::length_error("OhcBroadPhase: more than 2^32/3 vertices in one object");
  }
  if (c.next_order.size() == n) {
    // A cut's remap: the old order without the removed triangles (remap_object).
    c.order = std::move(c.next_order);
    c.next_order.clear();
    c.ordered.resize(n);
    for (std::uint32_t t = 0; t < n; ++t) c.ordered[t] = object.triangles[c.order[t]];
  } else {
    c.next_order.clear();
    morton_order(c, object);
  }
  build_cluster_lists(c, object);
}

void OhcBroadPhase::remap_object(std::size_t object, std::span<const std::uint32_t> triangle_origin) {
  if (object >= clusters_.size()) return;
  ObjectClusters& c = clusters_[object];
  c.next_order.clear();
  const std::size_t old_n = c.order.size();
  constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> now(old_n, kNone);
  for (std::size_t k = 0; k < triangle_origin.size(); ++k) {
    if (triangle_origin[k] >= old_n || now[triangle_origin[k]] != kNone) return;  // not one-to-one: sort anew
    now[triangle_origin[k]] = static_cast<std::uint32_t>(k);
  }
  for (const std::uint32_t old : c.order)
    if (now[old] != kNone) c.next_order.push_back(now[old]);
  if (c.next_order.size() != triangle_origin.size()) c.next_order.clear();
}

void OhcBroadPhase::morton_order(ObjectClusters& c, const CollisionObject& object) {
  const auto n = static_cast<std::uint32_t>(object.triangles.size());
  // Morton order of the centroids (21 bits per axis over the centroids' box): consecutive
  // triangles are close, so clusters of consecutive triangles are compact patches.
  Aabb centre_box;
  std::vector<Vec3> centres(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const Triangle& tri = object.triangles[t];
    centres[t] = (object.positions[tri[0]] + object.positions[tri[1]] + object.positions[tri[2]]) / 3.0;
    if (centres[t].allFinite()) centre_box.expand(centres[t]);
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  const Vec3 extent = centre_box.is_empty() ? Vec3(Vec3::Ones()) : Vec3(centre_box.size().cwiseMax(1e-300));
  for (std::uint32_t t = 0; t < n; ++t) {
    std::uint64_t code = 0;
    if (centres[t].allFinite() && !centre_box.is_empty()) {
      for (int k = 0; k < 3; ++k) {
        const Real u = std::clamp((centres[t][k] - centre_box.min[k]) / extent[k], 0.0, 1.0);
        code |= spread_bits(static_cast<std::uint64_t>(u * 2097151.0)) << k;
      }
    }
    keyed[t] = {code, t};
  }
  std::sort(keyed.begin(), keyed.end());
  c.order.resize(n);
  c.ordered.resize(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    c.order[t] = keyed[t].second;
    c.ordered[t] = object.triangles[keyed[t].second];
  }
}

void OhcBroadPhase::build_cluster_lists(ObjectClusters& c, const CollisionObject& object) {
  const auto n = static_cast<std::uint32_t>(object.triangles.size());
  const std::uint32_t clusters = (n + kClusterTriangles - 1) / kClusterTriangles;
  c.vertex_start.assign(clusters + 1, 0);
  c.vertices.clear();
  c.vertices.reserve(3 * static_cast<std::size_t>(n) + ohc_detail::kRefitPrefetch);
  std::vector<std::uint32_t> ids;
  // Each list's distinct vertices: a vertex is taken the first time its list meets it (seen:
  // the list's number + 1), then the few distinct ones are sorted (a sort of all three corners of
  // 32 triangles, then unique, cost twice as much).
  std::vector<std::uint32_t> seen(object.positions.size(), 0);
  std::uint32_t list = 0;
  for (std::uint32_t k = 0; k < clusters; ++k) {
    ids.clear();
    ++list;
    for (std::uint32_t t = k * kClusterTriangles; t < std::min(n, (k + 1) * kClusterTriangles); ++t) {
      for (const std::uint32_t v : object.triangles[c.order[t]])
        if (seen[v] != list) seen[v] = list, ids.push_back(v);
    }
    std::sort(ids.begin(), ids.end());
    // Stored as offsets in doubles (3 × id): the refit then addresses positions + offset
    // directly, one instruction less per vertex than scaling an id by 24 bytes.
    for (const std::uint32_t v : ids) c.vertices.push_back(3 * v);
    c.vertex_start[k + 1] = static_cast<std::uint32_t>(c.vertices.size());
  }
  const std::uint32_t groups = (clusters + kGroupClusters - 1) / kGroupClusters;
  c.group_start.assign(groups + 1, 0);
  c.group_vertices.clear();
  for (std::uint32_t g = 0; g < groups; ++g) {
    ids.clear();
    ++list;
    for (auto it = c.vertices.begin() + c.vertex_start[g * kGroupClusters];
         it != c.vertices.begin() + c.vertex_start[std::min(clusters, (g + 1) * kGroupClusters)]; ++it)
      if (seen[*it / 3] != list) seen[*it / 3] = list, ids.push_back(*it);
    std::sort(ids.begin(), ids.end());
    c.group_vertices.insert(c.group_vertices.end(), ids.begin(), ids.end());
    c.group_start[g + 1] = static_cast<std::uint32_t>(c.group_vertices.size());
  }
  // Padding read only by the refit's prefetch (vertex 0 exists whenever a cluster does).
  c.vertices.insert(c.vertices.end(), ohc_detail::kRefitPrefetch, 0u);
  c.group_vertices.insert(c.group_vertices.end(), ohc_detail::kRefitPrefetch, 0u);
  c.boxes.resize(clusters);
  c.regions.assign(clusters, Aabb{});
  c.groups.resize(groups);
  c.refitted.assign(groups, 0);
  c.touched.clear();
  c.touched.reserve(clusters);
  c.prim_first.assign(clusters, 0);
  c.prim_count.assign(clusters, 0);
}

void OhcBroadPhase::expand_region(std::uint32_t object, std::uint32_t cluster, const Aabb& box) {
  ObjectClusters& c = clusters_[object];
  // An expanded region is never empty again (box is non-empty), so this lists each cluster once.
  if (c.regions[cluster].is_empty()) c.touched.push_back(cluster);
  c.regions[cluster].expand(box);
}

Aabb OhcBroadPhase::refit_groups(ObjectClusters& c, const CollisionObject& object, bool simd, bool all_clusters) {
  Aabb box;
  if (c.boxes.empty()) return box;
  // The positions as flat doubles (Vec3 is three packed doubles); ids are offsets into them.
  const Real* p = object.positions.data()->data();
  const bool prefetch = object.positions.size() > ohc_detail::kRefitPrefetchVertices;
  Real lo[3];
  Real hi[3];
  if (c.groups.size() <= 2) {
    // A small object (a tool): its clusters are usually all needed, so their boxes come first
    // and the groups' are their unions (a NaN box left out), which reads each vertex less often.
    ohc_detail::refit_lists(p, c.vertices.data(), c.vertex_start.data(), c.boxes.size(), c.boxes.data(), lo, hi,
                            false, simd, prefetch);
    for (std::size_t g = 0; g < c.groups.size(); ++g) {
      Aabb group;
      for (std::size_t k = g * kGroupClusters; k < std::min(c.boxes.size(), (g + 1) * kGroupClusters); ++k) {
        for (int a = 0; a < 3; ++a) {
          group.min[a] = std::min(group.min[a], c.boxes[k].min[a]);
          group.max[a] = std::max(group.max[a], c.boxes[k].max[a]);
        }
      }
      c.groups[g] = group;
    }
    std::fill(c.refitted.begin(), c.refitted.end(), std::uint8_t{1});
  } else {
    ohc_detail::refit_lists(p, c.group_vertices.data(), c.group_start.data(), c.groups.size(), c.groups.data(), lo,
                            hi, true, simd, prefetch);
    std::fill(c.refitted.begin(), c.refitted.end(), std::uint8_t{0});
    if (all_clusters) {
      for (std::size_t g = 0; g < c.groups.size(); ++g) refit_group_clusters(c, object, g, simd);
    }
  }
  box.min = Vec3(lo[0], lo[1], lo[2]);
  box.max = Vec3(hi[0], hi[1], hi[2]);
  // The same inflation as object_box() (of the referenced vertices only).
  return box.inflated(kBoxMargin * box.size().maxCoeff());
}

void OhcBroadPhase::refit_group_clusters(ObjectClusters& c, const CollisionObject& object, std::size_t g, bool simd) {
  if (c.refitted[g]) return;
  c.refitted[g] = 1;
  const std::size_t first = g * kGroupClusters;
  const std::size_t count = std::min<std::size_t>(kGroupClusters, c.boxes.size() - first);
  Real lo[3];
  Real hi[3];
  ohc_detail::refit_lists(object.positions.data()->data(), c.vertices.data(), c.vertex_start.data() + first, count,
                          c.boxes.data() + first, lo, hi, false, simd,
                          object.positions.size() > ohc_detail::kRefitPrefetchVertices);
}

void OhcBroadPhase::cluster_cascade(std::span<const CollisionObject> objects, std::uint32_t i, std::uint32_t j) {
  // The clusters of i and j whose grown boxes touch the overlap of the object boxes, swept on
  // x: sorted by lower x, each item meets the later ones that start before it ends. A pair of
  // different sides whose grown boxes overlap adds their overlap to both clusters' regions.
  // Correctness: if triangles s of i and t of j have a common point x in their inflated boxes,
  // x lies in the grown boxes of their clusters (a triangle's margin is at most its object's
  // margin bound) and in both object boxes, so both clusters are swept, the later one in x order
  // is met by the earlier one, and x ends up in both clusters' regions.
  const Aabb overlap = boxes_[i].intersection(boxes_[j]);
  sweep_.clear();
  for (std::uint32_t side = 0; side < 2; ++side) {
    const std::uint32_t object = side == 0 ? i : j;
    ObjectClusters& c = clusters_[object];
    const Real margin = margins_[object];
    // Groups of kGroupClusters clusters first: a group box holds its clusters' vertices (min and
    // max are exact, and growing by the margin is monotone), so a group whose grown box misses
    // the overlap has no cluster that touches it; only the groups that pass have their clusters'
    // boxes refitted. (A NaN coordinate is left out of the group box; that cluster's own test
    // below fails anyway.)
    for (std::size_t g = 0; g < c.groups.size(); ++g) {
      if (!c.groups[g].inflated(margin).overlaps(overlap)) continue;
      refit_group_clusters(c, objects[object], g, settings_.simd);
      const auto first = static_cast<std::uint32_t>(g * kGroupClusters);
      const auto last = static_cast<std::uint32_t>(std::min<std::size_t>(c.boxes.size(), first + kGroupClusters));
      for (std::uint32_t k = first; k < last; ++k) {
        const Aabb grown = c.boxes[k].inflated(margin);
        // A box with a NaN fails this, so the sort below never compares a NaN.
        if (grown.overlaps(overlap)) sweep_.push_back({grown, side, k});
      }
    }
  }
  // Few clusters on the two sides (the usual case: a tool against the patch it presses on):
  // every pair of the two sides is tested, which costs less than sorting for the sweep. The same
  // pairs either way; only their order differs.
  const auto second = std::find_if(sweep_.begin(), sweep_.end(), [](const SweepItem& item) { return item.side == 1; });
  const auto side0 = static_cast<std::size_t>(second - sweep_.begin());
  if (side0 * (sweep_.size() - side0) <= kAllPairsClusters) {
    for (std::size_t a = 0; a < side0; ++a) {
      const SweepItem& p = sweep_[a];
      for (std::size_t b = side0; b < sweep_.size(); ++b) {
        const SweepItem& q = sweep_[b];
        if (!p.box.overlaps(q.box)) continue;
        const Aabb both = p.box.intersection(q.box);
        expand_region(i, p.cluster, both);
        expand_region(j, q.cluster, both);
        cluster_pair_list_.push_back({both, i, p.cluster, j, q.cluster});
        ++stats_.cluster_pairs;
      }
    }
    return;
  }
  std::sort(sweep_.begin(), sweep_.end(), [](const SweepItem& a, const SweepItem& b) {
    if (a.box.min.x() != b.box.min.x()) return a.box.min.x() < b.box.min.x();
    if (a.side != b.side) return a.side < b.side;
    return a.cluster < b.cluster;
  });
  // Steps are bounded by a multiple of the clusters (so O(primitives) whatever the geometry);
  // past it every swept cluster simply gets its box's overlap with the object overlap (what the
  // object level alone would allow it), which is still exact.
  const std::size_t budget = 16 * sweep_.size() + 1024;
  std::size_t steps = 0;
  const std::size_t count = sweep_.size();
  for (std::size_t a = 0; a < count; ++a) {
    const SweepItem& p = sweep_[a];
    for (std::size_t b = a + 1; b < count && sweep_[b].box.min.x() <= p.box.max.x(); ++b) {
      if (++steps > budget) {
        sweeps_complete_ = false;  // the cluster pairs are not all known: hash this frame
        for (const SweepItem& item : sweep_) {
          expand_region(item.side == 0 ? i : j, item.cluster, item.box.intersection(overlap));
        }
        return;
      }
      const SweepItem& q = sweep_[b];
      if (p.side == q.side || !p.box.overlaps(q.box)) continue;
      const Aabb both = p.box.intersection(q.box);
      expand_region(p.side == 0 ? i : j, p.cluster, both);
      expand_region(q.side == 0 ? i : j, q.cluster, both);
      const bool p_first = p.side == 0;
      cluster_pair_list_.push_back({both, i, p_first ? p.cluster : q.cluster, j, p_first ? q.cluster : p.cluster});
      ++stats_.cluster_pairs;
    }
  }
}

void OhcBroadPhase::cell_range(Primitive& prim, Real inv_h) {
#if defined(__SSE2__)
  // cell_of() on two coordinates at a time, bit for bit: min and max are six consecutive doubles
  // and lo, hi six consecutive int32 (static_asserts in the header), taken as three pairs.
  // _mm_min_pd/_mm_max_pd return their second operand when one is NaN, so a NaN stays NaN
  // through the clamp and converts to INT32_MIN, as in cell_of().
  const __m128d scale = _mm_set1_pd(inv_h);
  const __m128d upper = _mm_set1_pd(kCellClamp);
  const __m128d lower = _mm_set1_pd(-kCellClamp);
  const Real* x = prim.min.data();
  std::int32_t* out = prim.lo;
  for (int pair = 0; pair < 3; ++pair) {
    const __m128d v = _mm_max_pd(lower, _mm_min_pd(upper, _mm_mul_pd(_mm_loadu_pd(x + 2 * pair), scale)));
    const __m128i t = _mm_cvttpd_epi32(v);
    // −1 where the truncation went up (negative non-integers): the 64-bit masks' low halves.
    const __m128i up = _mm_shuffle_epi32(_mm_castpd_si128(_mm_cmpgt_pd(_mm_cvtepi32_pd(t), v)), _MM_SHUFFLE(3, 3, 2, 0));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 2 * pair), _mm_add_epi32(t, up));
  }
#else
  for (int k = 0; k < 3; ++k) {
    prim.lo[k] = cell_of(prim.min[k], inv_h);
    prim.hi[k] = cell_of(prim.max[k], inv_h);
  }
#endif
}

void OhcBroadPhase::find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) {
  out.clear();
  stats_ = {};
  primitives_.clear();
  cluster_pair_list_.clear();
  sweeps_complete_ = true;
  if (objects.size() < 2) return;
  // 1. Object boxes and the tested, overlapping pairs (and, with the cluster level, their
  //    overlapping cluster pairs).
  refit_objects(objects);
  find_overlapping_objects(objects);
  if (stats_.objects_overlapping == 0) return;
  // 2. The cascade: the triangles of each object whose box touches its region.
  const std::uint32_t opened = open_clusters(objects);
  stats_.primitives_hashed = opened;
  if (opened == 0) return;
  if (cluster_pairs_suffice(opened)) {
    stats_.cluster_pair_path = true;
    emit_cluster_pairs(objects, out, opened);
    stats_.candidate_pairs = out.size();
    return;
  }
  // 3.–5. The cell hash over the opened triangles.
  const Real rms_edge = copy_opened_to_primitives(objects, opened);
  CellBlock block;
  const std::uint64_t entry_count = assign_cells(objects.size(), rms_edge, block);
  const std::uint32_t mask = sort_entries_by_slot(entry_count);
  emit_slot_pairs(objects, out, entry_count, mask);
  std::uint64_t cells = 1;
  for (int k = 0; k < 3; ++k) cells *= static_cast<std::uint64_t>(static_cast<std::int64_t>(block.hi[k]) - block.lo[k] + 1);
  stats_.empty_cells = cells - stats_.cells_touched;
  stats_.candidate_pairs = out.size();
}

void OhcBroadPhase::refit_objects(std::span<const CollisionObject> objects) {
  const auto n = static_cast<std::uint32_t>(objects.size());
  boxes_.resize(n);
  regions_.assign(n, Aabb{});
  tested_.assign(static_cast<std::size_t>(n) * n, 0);
  if (clusters_.size() < n) clusters_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    ObjectClusters& c = clusters_[i];
    const CollisionObject& object = objects[i];
    if (c.triangles != object.triangles.data() || c.triangle_count != object.triangles.size() ||
        c.vertex_count != object.positions.size()) {
      build_clusters(c, object);  // first frame or another object: allocates
    }
    // Without the cluster level every cluster may open: all their boxes now.
    boxes_[i] = refit_groups(c, object, settings_.simd, !by_cluster());
  }
  margins_.resize(n);
  std::size_t all_clusters = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    // Bound on the margin of each of the object's triangle boxes (kBoxMargin of a side that is
    // at most the object's).
    margins_[i] = boxes_[i].is_empty() ? 0.0 : kBoxMargin * boxes_[i].size().maxCoeff();
    // Last frame's cluster regions back to empty: only those it touched (O(touched), not
    // O(clusters): the 720K sheet has 22,500 clusters and touches ~50).
    ObjectClusters& c = clusters_[i];
    for (const std::uint32_t k : c.touched) c.regions[k] = Aabb{};
    c.touched.clear();
    if (by_cluster()) all_clusters += c.boxes.size();
  }
  if (by_cluster()) sweep_.reserve(all_clusters);  // a pair sweeps at most every cluster
}

void OhcBroadPhase::find_overlapping_objects(std::span<const CollisionObject> objects) {
  const auto n = static_cast<std::uint32_t>(objects.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    if (boxes_[i].is_empty()) continue;
    for (std::uint32_t j = i + 1; j < n; ++j) {
      if (boxes_[j].is_empty() || !tested(objects[i].role, objects[j].role)) continue;
      if (!boxes_[i].overlaps(boxes_[j])) continue;
      tested_[static_cast<std::size_t>(i) * n + j] = 1;
      tested_[static_cast<std::size_t>(j) * n + i] = 1;
      ++stats_.objects_overlapping;
      if (settings_.cascade) {
        const Aabb overlap = boxes_[i].intersection(boxes_[j]);
        regions_[i].expand(overlap);
        regions_[j].expand(overlap);
        if (by_cluster()) cluster_cascade(objects, i, j);
      } else {
        regions_[i] = boxes_[i];
        regions_[j] = boxes_[j];
      }
    }
  }
}

// Correctness of the cascade: if triangles s of object i and t of object j intersect, a common
// point x lies in both inflated triangle boxes and so in both object boxes, hence in
// box_i ∩ box_j ⊆ region_i ∩ region_j: both pass and their clipped boxes still share x.
std::uint32_t OhcBroadPhase::open_clusters(std::span<const CollisionObject> objects) {
  const auto n = static_cast<std::uint32_t>(objects.size());
  const ohc_detail::OpenedArrays opened_arrays = reserve_opened(objects);
  // Eight triangles at a time where the CPU has AVX-512 (the same triangles and boxes).
  const bool avx512 = settings_.simd && cpu_has_avx512();
  const bool cluster_level = by_cluster();
  std::uint32_t opened = 0;  // triangles that passed
  for (std::uint32_t i = 0; i < n; ++i) {
    const Aabb& region = regions_[i];
    if (region.is_empty()) continue;
    const CollisionObject& object = objects[i];
    ObjectClusters& c = clusters_[i];
    const Vec3* p = object.positions.data();
    // A triangle's margin is at most kBoxMargin·(object size): test the raw cluster boxes
    // against the region grown by that much, then clip the inflated triangle boxes.
    const Aabb grown = region.inflated(margins_[i]);
    const auto triangle_count = static_cast<std::uint32_t>(object.triangles.size());
    // With the cluster level only the clusters it touched can open, in ascending order as a
    // scan over all of them would visit them.
    if (cluster_level) std::sort(c.touched.begin(), c.touched.end());
    const std::size_t to_visit = cluster_level ? c.touched.size() : c.boxes.size();
    for (std::size_t v = 0; v < to_visit; ++v) {
      const std::uint32_t k = cluster_level ? c.touched[v] : static_cast<std::uint32_t>(v);
      const std::uint32_t first_prim = opened;
      if (cluster_level) {
        c.prim_first[k] = first_prim;
        c.prim_count[k] = 0;
      }
      if (!c.boxes[k].overlaps(grown)) continue;
      // With the cluster level, the cluster's own region (the overlaps of its grown box with
      // partner clusters' grown boxes) narrows the object's; a common point of two inflated
      // triangle boxes lies in both (see cluster_cascade()), so clipping to it loses no pair.
      Aabb clip = region;
      Aabb clip_grown = grown;
      if (cluster_level) {
        clip = region.intersection(c.regions[k]);
        if (clip.is_empty()) continue;
        clip_grown = clip.inflated(margins_[i]);
      }
      ++stats_.clusters_opened;
      const Real g_lo[3] = {clip_grown.min.x(), clip_grown.min.y(), clip_grown.min.z()};
      const Real g_hi[3] = {clip_grown.max.x(), clip_grown.max.y(), clip_grown.max.z()};
      const std::uint32_t begin = k * kClusterTriangles;
      const std::uint32_t end = std::min(triangle_count, (k + 1) * kClusterTriangles);
      if (avx512) {
        const Real c_lo[3] = {clip.min.x(), clip.min.y(), clip.min.z()};
        const Real c_hi[3] = {clip.max.x(), clip.max.y(), clip.max.z()};
        opened = ohc_detail::open_cluster_avx512(p, c.ordered.data() + begin, c.order.data() + begin, end - begin, i,
                                                 c_lo, c_hi, g_lo, g_hi, opened_arrays, opened);
      } else {
        opened = open_cluster_portable(p, c.ordered.data(), c.order.data(), begin, end, clip, g_lo, g_hi, opened_arrays,
                                       opened, [&](std::uint32_t at, std::uint32_t t) { opened_ids_[at] = {i, t}; });
      }
      if (cluster_level) c.prim_count[k] = opened - first_prim;
    }
  }
  return opened;
}

// The boxes go to one array per axis and side (what the box tests read four or eight at a
// time), sized for every triangle of the clusters that may open.
ohc_detail::OpenedArrays OhcBroadPhase::reserve_opened(std::span<const CollisionObject> objects) {
  std::size_t bound = 0;
  for (std::uint32_t i = 0; i < objects.size(); ++i) {
    if (regions_[i].is_empty()) continue;
    bound += by_cluster() ? kClusterTriangles * clusters_[i].touched.size() : objects[i].triangles.size();
  }
  if (opened_stride_ < bound + 8) {
    opened_stride_ = bound + 8;
    opened_boxes_.assign((6 + 2 * ohc_detail::kDopAxes) * opened_stride_, 0.0);
    opened_ids_.resize(opened_stride_);
  }
  static_assert(sizeof(OpenedId) == 8 && offsetof(OpenedId, object) == 0, "the AVX-512 kernel writes ids as 64 bits");
  ohc_detail::OpenedArrays arrays{};
  for (int axis = 0; axis < 3; ++axis) {
    arrays.lo[axis] = opened_boxes_.data() + static_cast<std::size_t>(axis) * opened_stride_;
    arrays.hi[axis] = opened_boxes_.data() + static_cast<std::size_t>(3 + axis) * opened_stride_;
  }
  for (int k = 0; k < ohc_detail::kDopAxes; ++k) {
    const auto lower = static_cast<std::size_t>(6 + k);
    arrays.dop_lo[k] = opened_boxes_.data() + lower * opened_stride_;
    arrays.dop_hi[k] = opened_boxes_.data() + (lower + ohc_detail::kDopAxes) * opened_stride_;
  }
  arrays.ids = reinterpret_cast<std::uint64_t*>(opened_ids_.data());
  return arrays;
}

// The cluster-pair path when the pairs are all known and their box tests are few enough to
// stay O(primitives): no cells at all.
bool OhcBroadPhase::cluster_pairs_suffice(std::uint32_t opened) const {
  if (!by_cluster() || !sweeps_complete_ || !(settings_.max_pair_tests_per_primitive > 0)) return false;
  Real tests = 0;
  for (const ClusterPair& cp : cluster_pair_list_) {
    tests += static_cast<Real>(clusters_[cp.i].prim_count[cp.cluster_i]) *
             static_cast<Real>(clusters_[cp.j].prim_count[cp.cluster_j]);
  }
  return tests <= settings_.max_pair_tests_per_primitive * static_cast<Real>(opened) + 1024.0;
}

Real OhcBroadPhase::copy_opened_to_primitives(std::span<const CollisionObject> objects, std::uint32_t opened) {
  // The hash's primitives (boxes and cell ranges together), and the edge lengths for its cells.
  const Real* box_lo[3] = {opened_boxes_.data(), opened_boxes_.data() + opened_stride_,
                           opened_boxes_.data() + 2 * opened_stride_};
  const Real* box_hi[3] = {box_lo[2] + opened_stride_, box_lo[2] + 2 * opened_stride_, box_lo[2] + 3 * opened_stride_};
  primitives_.resize(opened);
  Real edge_sum2 = 0;  // Σ squared edge lengths of the hashed primitives
  for (std::uint32_t e = 0; e < opened; ++e) {
    Primitive& prim = primitives_[e];
    prim.min = Vec3(box_lo[0][e], box_lo[1][e], box_lo[2][e]);
    prim.max = Vec3(box_hi[0][e], box_hi[1][e], box_hi[2][e]);
    prim.object = opened_ids_[e].object;
    prim.triangle = opened_ids_[e].triangle;
    const CollisionObject& object = objects[prim.object];
    const Triangle& tri = object.triangles[prim.triangle];
    const Vec3& a = object.positions[tri[0]];
    const Vec3& b = object.positions[tri[1]];
    const Vec3& cc = object.positions[tri[2]];
    edge_sum2 += (b - a).squaredNorm() + (cc - b).squaredNorm() + (a - cc).squaredNorm();
  }
  const std::size_t edge_count = 3 * static_cast<std::size_t>(opened);
  // Root mean square edge length: one square root per frame instead of three per primitive.
  return std::sqrt(edge_sum2 / static_cast<Real>(edge_count));
}

// 3. Cell size and cell ranges; double the cell while a few huge boxes would need too many.
std::uint64_t OhcBroadPhase::assign_cells(std::size_t object_count, Real rms_edge, CellBlock& block) {
  Real h = settings_.cell_size;
  if (!(h > 0) || !std::isfinite(h)) h = settings_.auto_cell_factor * rms_edge;
  if (!(h > 0) || !std::isfinite(h)) {
    Aabb all;
    for (std::size_t i = 0; i < object_count; ++i) all.expand(regions_[i]);
    h = all.is_empty() ? 1.0 : all.size().maxCoeff();
    if (!(h > 0) || !std::isfinite(h)) h = 1.0;
  }
  const Real budget = std::max<Real>(settings_.max_cells_per_primitive, 1.0) *
                          static_cast<Real>(primitives_.size()) + 64.0;
  std::uint64_t entry_count = 0;
  for (;;) {
    const Real inv_h = 1.0 / h;
    Real total = 0;
    for (int k = 0; k < 3; ++k) {
      block.lo[k] = std::numeric_limits<std::int32_t>::max();
      block.hi[k] = std::numeric_limits<std::int32_t>::min();
    }
    for (Primitive& prim : primitives_) {
      cell_range(prim, inv_h);
      Real cells = 1;
      for (int k = 0; k < 3; ++k) {
        cells *= static_cast<Real>(static_cast<std::int64_t>(prim.hi[k]) - prim.lo[k]) + 1;  // up to 2^31 + 1
        block.lo[k] = std::min(block.lo[k], prim.lo[k]);
        block.hi[k] = std::max(block.hi[k], prim.hi[k]);
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
  return entry_count;
}

// 4. Counting sort of the entries by slot: a table of a power of two ≥ 2·entries slots, in a
//    buffer that only grows (a frame that needs fewer slots uses a prefix of it, so the
//    clearing and prefix sum below stay O(entries)). Leaves slot_start_[s] = first entry of
//    slot s (and [s + 1] its end); returns the slot mask.
std::uint32_t OhcBroadPhase::sort_entries_by_slot(std::uint64_t entry_count) {
  const std::size_t table = std::bit_ceil(std::max<std::size_t>(16, 2 * static_cast<std::size_t>(entry_count)));
  if (slot_start_.size() < table + 1) slot_start_.resize(table + 1);
  const auto mask = static_cast<std::uint32_t>(table - 1);
  stats_.table_size = static_cast<std::uint32_t>(table);
  std::uint32_t* start = slot_start_.data();
  std::fill(start, start + table + 1, 0u);
  // One pass over the cells of every primitive, in ascending primitive order: each entry is
  // staged with its slot (hashed once) and counted.
  staged_.resize(entry_count);
  staged_slots_.resize(entry_count);
  {
    Entry* staged = staged_.data();
    std::uint32_t* slots = staged_slots_.data();
    std::size_t e = 0;
    for (std::uint32_t k = 0; k < primitives_.size(); ++k) {
      const Primitive& prim = primitives_[k];
      for (std::int32_t z = prim.lo[2]; z <= prim.hi[2]; ++z)
        for (std::int32_t y = prim.lo[1]; y <= prim.hi[1]; ++y)
          for (std::int32_t x = prim.lo[0]; x <= prim.hi[0]; ++x) {
            const std::uint32_t slot = cell_hash(x, y, z) & mask;
            ++start[slot];
            staged[e] = {x, y, z, k};
            slots[e++] = slot;
          }
    }
  }
  start[table] = inclusive_prefix_sum(start, table);
  entries_.resize(entry_count);
  // emit_cell_pairs scratch, a cell's worth (the box arrays readable 3 past a cell's end).
  if (cell_starts_.size() < entries_.size()) cell_starts_.resize(entries_.size());
  if (cell_hits_.size() < entries_.size() + 8) cell_hits_.resize(entries_.size() + 8);
  if (cell_groups_.size() < entries_.size() + 1) cell_groups_.resize(entries_.size() + 1);
  if (cell_stride_ < entries_.size() + 4) {
    cell_stride_ = entries_.size() + 4;
    cell_boxes_.assign(6 * cell_stride_, 0.0);
  }
  Entry* entries = entries_.data();
  // The staged entries backwards, each slot filled from its back: every slot ends up in
  // ascending primitive order (emit_slot_pairs relies on it).
  for (std::size_t e = entry_count; e-- > 0;) entries[--start[staged_slots_[e]]] = staged_[e];
  return mask;
}

// 5. Per slot: sort by (cell, primitive) so hash collisions fall apart into cells, then
//    classify each cell and emit pairs from the potential-colliding ones.
void OhcBroadPhase::emit_slot_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out,
                                    std::uint64_t entry_count, std::uint32_t mask) {
  const std::uint32_t* start = slot_start_.data();
  Entry* entries = entries_.data();
  const auto same_cell = [](const Entry& a, const Entry& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
  const auto entry_less = [](const Entry& a, const Entry& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    if (a.z != b.z) return a.z < b.z;
    return a.primitive < b.primitive;
  };
  // The entries lie slot after slot in ascending slot order, so walking them visits exactly the
  // non-empty slots in the order of a scan over the table (most slots are empty).
  for (std::uint32_t b = 0, e = 0; b < entry_count; b = e) {
    e = start[(cell_hash(entries[b].x, entries[b].y, entries[b].z) & mask) + 1];
    if (e - b == 1) {
      ++stats_.cells_touched;
      ++stats_.solo_cells;
      continue;
    }
    // The slot is in ascending primitive order already; it needs sorting only when a hash
    // collision mixed cells in it (rare: the table has ≥ 2 slots per entry).
    bool one_cell = true;
    for (std::uint32_t i = b + 1; i < e && one_cell; ++i) one_cell = same_cell(entries[i], entries[b]);
    if (one_cell) {
      // nothing to do
    } else if (e - b <= 16) {
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
      while (r_end < e && same_cell(entries[r_end], entries[r])) ++r_end;
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
}

}  // namespace trocar
