#include "trocar/geometry/signed_distance.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "trocar/core/cpu_features.h"
#include "trocar/core/error.h"

namespace trocar {
namespace {

Vec3 normalized_or_zero(const Vec3& v) {
  const Real len = v.norm();
  return len > 0 ? Vec3(v / len) : Vec3::Zero();
}

/// True when triangle abc is certainly no nearer to p than √best: p's distance to the
/// triangle's plane already reaches it. Cheaper than a closest point (no branches on regions), it
/// rejects most of the triangles that pass the box test in a query.
///
/// The bound is made safe against rounding. With u = b − a, v = c − a and n the computed u × v
/// (off the exact normal by at most γ|u||v|), every triangle point x has |n·(x − a)| ≤
/// γ|u||v|·max(|u|, |v|), and h = n·(p − a) is computed within γ|n||p − a|. So for the nearest
/// triangle point y, |p − y| ≥ (|h| − slack)/|n| with slack = γ(|u||v|max(|u|,|v|) + |n||p − a|).
/// γ = 1e-14 is ~50 times the rounding of these products; 1-norms stand in for the lengths (they
/// are larger), and a relative 1e-12 covers the rounding of the final comparison.
bool plane_is_no_nearer(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Real best) {
  const Vec3 u = b - a;
  const Vec3 v = c - a;
  const Vec3 n = u.cross(v);
  const Vec3 pa = p - a;
  const Real h = std::abs(n.dot(pa));
  const Real lu = u.lpNorm<1>();
  const Real lv = v.lpNorm<1>();
  const Real slack = 1e-14 * (lu * lv * std::max(lu, lv) + n.lpNorm<1>() * pa.lpNorm<1>());
  if (!(h > slack)) return false;
  return (h - slack) * (h - slack) >= best * n.squaredNorm() * (1 + 1e-12);
}

/// gap[j] = squared distance from p to box j of `count` boxes stored per coordinate (lo[a][j],
/// hi[a][j]); the same values as AabbTree::distance_squared. Branch-free, so it vectorises.
inline __attribute__((always_inline)) void box_gaps(const Real* const lo[3], const Real* const hi[3],
                                                    const Vec3& p, std::size_t count, Real* gap) {
  for (std::size_t j = 0; j < count; ++j) gap[j] = 0;
  for (int a = 0; a < 3; ++a) {
    const Real pa = p[a];
    for (std::size_t j = 0; j < count; ++j) {
      const Real below = lo[a][j] - pa;
      const Real above = pa - hi[a][j];
      const Real g = (below > 0 ? below : 0) + (above > 0 ? above : 0);
      gap[j] += g * g;
    }
  }
}

void box_gaps_portable(const Real* const lo[3], const Real* const hi[3], const Vec3& p, std::size_t count,
                       Real* gap) {
  box_gaps(lo, hi, p, count, gap);
}

#if defined(__x86_64__)
// The same loop, 4 doubles wide. No FMA in the target, so no contraction: the same bits.
__attribute__((target("avx2"))) void box_gaps_avx2(const Real* const lo[3], const Real* const hi[3],
                                                   const Vec3& p, std::size_t count, Real* gap) {
  box_gaps(lo, hi, p, count, gap);
}
#endif

}  // namespace

MeshDistance::MeshDistance(std::span<const Vec3> positions, std::span<const Triangle> triangles)
    : positions_(positions.begin(), positions.end()),
      triangles_(triangles.begin(), triangles.end()) {
  const std::size_t nt = triangles_.size();
  for (std::size_t t = 0; t < nt; ++t) {
    for (const std::uint32_t v : triangles_[t]) {
      if (v >= positions_.size()) {
        throw Error("MeshDistance: triangle " + std::to_string(t) + " refers to vertex " +
                    std::to_string(v) + ", but the mesh has " +
                    std::to_string(positions_.size()) + " vertices");
      }
    }
  }
  // Edge map: sort (min vertex, max vertex, slot) so the slots of one edge are adjacent.
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> keys;
  keys.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles_[t][static_cast<std::size_t>(k)];
      const std::uint32_t b = triangles_[t][static_cast<std::size_t>((k + 1) % 3)];
      keys.emplace_back(std::min(a, b), std::max(a, b),
                        static_cast<std::uint32_t>(3 * t + static_cast<std::size_t>(k)));
    }
  }
  std::sort(keys.begin(), keys.end());
  edge_of_slot_.assign(3 * nt, 0);
  edge_slots_.resize(keys.size());
  std::uint32_t edges = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i > 0 && (std::get<0>(keys[i]) != std::get<0>(keys[i - 1]) ||
                  std::get<1>(keys[i]) != std::get<1>(keys[i - 1]))) {
      ++edges;
      edge_first_.push_back(static_cast<std::uint32_t>(i));
    }
    if (i == 0) edge_first_.push_back(0);
    edge_of_slot_[std::get<2>(keys[i])] = edges;
    edge_slots_[i] = std::get<2>(keys[i]);  // the sort put one edge's slots in ascending order
  }
  if (!keys.empty()) edge_first_.push_back(static_cast<std::uint32_t>(keys.size()));
  // Corners by vertex (counting sort: corners come out in ascending order per vertex).
  vertex_first_.assign(positions_.size() + 1, 0);
  for (const Triangle& tri : triangles_)
    for (const std::uint32_t v : tri) ++vertex_first_[v + 1];
  for (std::size_t v = 0; v < positions_.size(); ++v) vertex_first_[v + 1] += vertex_first_[v];
  vertex_corners_.resize(3 * nt);
  std::vector<std::uint32_t> fill(vertex_first_.begin(), vertex_first_.end() - 1);
  for (std::size_t slot = 0; slot < 3 * nt; ++slot)
    vertex_corners_[fill[triangles_[slot / 3][slot % 3]]++] = static_cast<std::uint32_t>(slot);
  boxes_.resize(nt);
  update_boxes();
  tree_.build(boxes_);
}

void MeshDistance::refit(std::span<const Vec3> positions) {
  if (positions.size() != positions_.size()) {
    throw Error("MeshDistance::refit: got " + std::to_string(positions.size()) +
                " positions, but the mesh has " + std::to_string(positions_.size()) + " vertices");
  }
  std::copy(positions.begin(), positions.end(), positions_.begin());
  update_boxes();
  tree_.refit(boxes_);
}

Vec3 MeshDistance::face_normal(std::uint32_t t) const {
  const Triangle& tri = triangles_[t];
  const Vec3& a = positions_[tri[0]];
  return normalized_or_zero((positions_[tri[1]] - a).cross(positions_[tri[2]] - a));
}

Vec3 MeshDistance::weighted_corner_normal(std::uint32_t t, std::size_t k, const Vec3& n) const {
  // Angle-weighted vertex pseudonormal (Bærentzen & Aanæs 2005, eq. 2; Thürmer & Wüthrich
  // 1998): Σ α_i n_i over incident faces, α_i the face's angle at the vertex. The angle is
  // atan2(|u × v|, u·v), accurate for all angles (acos loses precision near 0 and π).
  const Triangle& tri = triangles_[t];
  const Vec3& p = positions_[tri[k]];
  const Vec3 u = positions_[tri[(k + 1) % 3]] - p;
  const Vec3 v = positions_[tri[(k + 2) % 3]] - p;
  return std::atan2(u.cross(v).norm(), u.dot(v)) * n;
}

Vec3 MeshDistance::vertex_pseudonormal(std::uint32_t v) const {
  // Summed from zero in ascending corner order: the same bits as a sweep over all triangles.
  Vec3 sum = Vec3::Zero();
  for (std::uint32_t i = vertex_first_[v]; i < vertex_first_[v + 1]; ++i) {
    const std::uint32_t t = vertex_corners_[i] / 3;
    sum += weighted_corner_normal(t, vertex_corners_[i] % 3, face_normal(t));
  }
  return normalized_or_zero(sum);
}

Vec3 MeshDistance::edge_pseudonormal(std::uint32_t t, int k) const {
  // Sum of the adjacent face normals (Bærentzen & Aanæs 2005, §3), in ascending slot order.
  const std::uint32_t e = edge_of_slot_[3 * t + static_cast<std::uint32_t>(k)];
  Vec3 sum = Vec3::Zero();
  for (std::uint32_t i = edge_first_[e]; i < edge_first_[e + 1]; ++i) sum += face_normal(edge_slots_[i] / 3);
  return normalized_or_zero(sum);
}

void MeshDistance::update_boxes() {
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Vec3& a = positions_[triangles_[t][0]];
    const Vec3& b = positions_[triangles_[t][1]];
    const Vec3& c = positions_[triangles_[t][2]];
    boxes_[t] = Aabb{a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
  }
}

SignedDistanceResult MeshDistance::finish(const Vec3& p, std::uint32_t t,
                                          const TriangleClosestPoint& c, Real d2) const {
  SignedDistanceResult r;
  if (t == kNoTriangle) return r;
  r.closest_point = c.point;
  r.triangle = t;
  r.feature = c.feature;
  r.feature_index = c.index;
  switch (c.feature) {
    case TriangleFeature::kFace: r.pseudonormal = face_normal(t); break;
    case TriangleFeature::kEdge: r.pseudonormal = edge_pseudonormal(t, c.index); break;
    case TriangleFeature::kVertex:
      r.pseudonormal = vertex_pseudonormal(triangles_[t][static_cast<std::size_t>(c.index)]);
      break;
  }
  const Real d = std::sqrt(d2);
  r.distance = (p - c.point).dot(r.pseudonormal) >= 0 ? d : -d;
  return r;
}

// Inlined: it is the inner loop of both searches.
[[gnu::always_inline]] inline void MeshDistance::offer(const Vec3& p, std::uint32_t t, Real& best_sq,
                                                       std::uint32_t& best_t, TriangleClosestPoint& best_c) const {
  const Triangle& tri = triangles_[t];
  const Vec3& a = positions_[tri[0]];
  const Vec3& b = positions_[tri[1]];
  const Vec3& c = positions_[tri[2]];
  if (plane_is_no_nearer(p, a, b, c, best_sq)) return;
  const TriangleClosestPoint q = closest_point_on_triangle(p, a, b, c);
  const Real d2 = (p - q.point).squaredNorm();
  if (d2 < best_sq) {
    best_sq = d2;
    best_t = t;
    best_c = q;
  }
}

SignedDistanceResult MeshDistance::signed_distance(const Vec3& p, std::uint32_t hint) const {
  Real best = std::numeric_limits<Real>::infinity();
  std::uint32_t best_t = kNoTriangle;
  TriangleClosestPoint best_c;
  if (hint < triangles_.size()) {
    // Seed the bound; the search below only takes strictly nearer triangles, so the distance
    // is the minimum over all triangles either way.
    const Triangle& tri = triangles_[hint];
    best_c = closest_point_on_triangle(p, positions_[tri[0]], positions_[tri[1]], positions_[tri[2]]);
    best = (p - best_c.point).squaredNorm();
    best_t = hint;
  }
  tree_.nearest(p, best, [&](std::uint32_t t, Real& best_sq) {
    // A triangle lies in its box and beside its plane: one no nearer than the bound by either
    // cannot win (the cheap tests skip most closest-point computations).
    if (AabbTree::distance_squared(boxes_[t], p) < best_sq) offer(p, t, best_sq, best_t, best_c);
  });
  return finish(p, best_t, best_c, best);
}

MeshDistance::BatchScratch::BatchScratch(std::size_t triangles) : ids_(triangles), gap_(triangles) {
  for (std::vector<Real>& v : box_) v.resize(triangles);
}

void MeshDistance::signed_distances(std::span<const Vec3> points, std::span<std::uint32_t> hints,
                                    std::span<SignedDistanceResult> results,
                                    BatchScratch& scratch) const {
  if (hints.size() != points.size() || results.size() != points.size()) {
    throw Error("MeshDistance::signed_distances: " + std::to_string(points.size()) + " points, " +
                std::to_string(hints.size()) + " hints, " + std::to_string(results.size()) + " results");
  }
  if (scratch.ids_.size() < triangles_.size()) {
    throw Error("MeshDistance::signed_distances: scratch for " + std::to_string(scratch.ids_.size()) +
                " triangles, the mesh has " + std::to_string(triangles_.size()));
  }
  // Seed: each point's squared distance to its hint triangle (a tree query when it has none).
  Aabb region;
  Real radius_squared = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec3& p = points[k];
    region.expand(p);
    SignedDistanceResult& r = results[k];
    if (hints[k] >= triangles_.size()) {
      r = signed_distance(p);
      hints[k] = r.triangle;
      if (r.triangle == kNoTriangle) {  // an empty mesh: every result is "no triangle"
        std::fill(results.begin(), results.end(), SignedDistanceResult{});
        std::fill(hints.begin(), hints.end(), kNoTriangle);
        return;
      }
    } else {
      const Triangle& tri = triangles_[hints[k]];
      const TriangleClosestPoint c = closest_point_on_triangle(p, positions_[tri[0]], positions_[tri[1]], positions_[tri[2]]);
      r.closest_point = c.point;
      r.triangle = hints[k];
      r.feature = c.feature;
      r.feature_index = c.index;
    }
    r.distance = (p - r.closest_point).squaredNorm();  // squared until finish()
    radius_squared = std::max(radius_squared, r.distance);
  }
  // A triangle nearer to some point than that point's seed is nearer to the region than the
  // largest seed, so the walk below finds every triangle that can improve on a seed.
  std::size_t count = 0;
  tree_.for_each_near(region, radius_squared, [&](std::uint32_t t) {
    const Aabb& box = boxes_[t];
    if (!(AabbTree::distance_squared(box, region) < radius_squared)) return;
    scratch.ids_[count] = t;
    for (int a = 0; a < 3; ++a) {
      scratch.box_[a][count] = box.min[a];
      scratch.box_[3 + a][count] = box.max[a];
    }
    ++count;
  });
  for (std::size_t k = 0; k < points.size(); ++k) results[k] = nearest_among(points[k], results[k], count, scratch);
  for (std::size_t k = 0; k < points.size(); ++k) hints[k] = results[k].triangle;
}

SignedDistanceResult MeshDistance::nearest_among(const Vec3& p, const SignedDistanceResult& seed,
                                                 std::size_t count, BatchScratch& scratch) const {
  // Squared distances from p to all candidate boxes first, in one vectorised pass.
  Real* gap = scratch.gap_.data();
  const Real* const lo[3] = {scratch.box_[0].data(), scratch.box_[1].data(), scratch.box_[2].data()};
  const Real* const hi[3] = {scratch.box_[3].data(), scratch.box_[4].data(), scratch.box_[5].data()};
#if defined(__x86_64__)
  if (cpu_has_avx2()) {
    box_gaps_avx2(lo, hi, p, count, gap);
  } else {
    box_gaps_portable(lo, hi, p, count, gap);
  }
#else
  box_gaps_portable(lo, hi, p, count, gap);
#endif
  Real best = seed.distance;  // squared
  std::uint32_t best_t = seed.triangle;
  TriangleClosestPoint best_c;
  best_c.point = seed.closest_point;
  best_c.feature = seed.feature;
  best_c.index = seed.feature_index;
  for (std::size_t j = 0; j < count; ++j) {
    if (gap[j] < best) offer(p, scratch.ids_[j], best, best_t, best_c);
  }
  return finish(p, best_t, best_c, best);
}

SignedDistanceResult MeshDistance::signed_distance_brute_force(const Vec3& p) const {
  Real best = std::numeric_limits<Real>::infinity();
  std::uint32_t best_t = kNoTriangle;
  TriangleClosestPoint best_c;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    const TriangleClosestPoint c =
        closest_point_on_triangle(p, positions_[tri[0]], positions_[tri[1]], positions_[tri[2]]);
    const Real d2 = (p - c.point).squaredNorm();
    if (d2 < best) {
      best = d2;
      best_t = static_cast<std::uint32_t>(t);
      best_c = c;
    }
  }
  return finish(p, best_t, best_c, best);
}

}  // namespace trocar
