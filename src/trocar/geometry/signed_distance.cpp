#include "trocar/geometry/signed_distance.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "trocar/core/error.h"

namespace trocar {
namespace {

Vec3 normalized_or_zero(const Vec3& v) {
  const Real len = v.norm();
  return len > 0 ? Vec3(v / len) : Vec3::Zero();
}

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
    // A triangle lies in its box: one no nearer than the bound cannot win (the cheap test
    // skips most closest-point computations in a leaf).
    if (!(AabbTree::distance_squared(boxes_[t], p) < best_sq)) return;
    const Triangle& tri = triangles_[t];
    const TriangleClosestPoint c =
        closest_point_on_triangle(p, positions_[tri[0]], positions_[tri[1]], positions_[tri[2]]);
    const Real d2 = (p - c.point).squaredNorm();
    if (d2 < best_sq) {
      best_sq = d2;
      best_t = t;
      best_c = c;
    }
  });
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
