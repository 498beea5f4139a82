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
  std::uint32_t edges = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i > 0 && (std::get<0>(keys[i]) != std::get<0>(keys[i - 1]) ||
                  std::get<1>(keys[i]) != std::get<1>(keys[i - 1]))) {
      ++edges;
    }
    edge_of_slot_[std::get<2>(keys[i])] = edges;
  }
  edge_normals_.assign(keys.empty() ? 0 : edges + 1, Vec3::Zero());
  face_normals_.assign(nt, Vec3::Zero());
  vertex_normals_.assign(positions_.size(), Vec3::Zero());
  boxes_.resize(nt);
  update_normals();
  update_boxes();
  tree_.build(boxes_);
}

void MeshDistance::refit(std::span<const Vec3> positions) {
  if (positions.size() != positions_.size()) {
    throw Error("MeshDistance::refit: got " + std::to_string(positions.size()) +
                " positions, but the mesh has " + std::to_string(positions_.size()) + " vertices");
  }
  std::copy(positions.begin(), positions.end(), positions_.begin());
  update_normals();
  update_boxes();
  tree_.refit(boxes_);
}

void MeshDistance::update_normals() {
  std::fill(vertex_normals_.begin(), vertex_normals_.end(), Vec3::Zero());
  std::fill(edge_normals_.begin(), edge_normals_.end(), Vec3::Zero());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    const Vec3& a = positions_[tri[0]];
    const Vec3& b = positions_[tri[1]];
    const Vec3& c = positions_[tri[2]];
    const Vec3 n = normalized_or_zero((b - a).cross(c - a));
    face_normals_[t] = n;
    // Angle-weighted vertex pseudonormal (Bærentzen & Aanæs 2005, eq. 2; Thürmer & Wüthrich
    // 1998): Σ α_i n_i over incident faces, α_i the face's angle at the vertex. The angle is
    // atan2(|u × v|, u·v), accurate for all angles (acos loses precision near 0 and π).
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3& p = positions_[tri[k]];
      const Vec3 u = positions_[tri[(k + 1) % 3]] - p;
      const Vec3 v = positions_[tri[(k + 2) % 3]] - p;
      const Real angle = std::atan2(u.cross(v).norm(), u.dot(v));
      vertex_normals_[tri[k]] += angle * n;
    }
    // Edge pseudonormal: sum of the adjacent face normals (Bærentzen & Aanæs 2005, §3).
    for (std::size_t k = 0; k < 3; ++k) edge_normals_[edge_of_slot_[3 * t + k]] += n;
  }
  for (Vec3& n : vertex_normals_) n = normalized_or_zero(n);
  for (Vec3& n : edge_normals_) n = normalized_or_zero(n);
}

void MeshDistance::update_boxes() {
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    Aabb box;
    for (const std::uint32_t v : triangles_[t]) box.expand(positions_[v]);
    boxes_[t] = box;
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
    case TriangleFeature::kFace: r.pseudonormal = face_normals_[t]; break;
    case TriangleFeature::kEdge: r.pseudonormal = edge_pseudonormal(t, c.index); break;
    case TriangleFeature::kVertex:
      r.pseudonormal = vertex_normals_[triangles_[t][static_cast<std::size_t>(c.index)]];
      break;
  }
  const Real d = std::sqrt(d2);
  r.distance = (p - c.point).dot(r.pseudonormal) >= 0 ? d : -d;
  return r;
}

SignedDistanceResult MeshDistance::signed_distance(const Vec3& p) const {
  Real best = std::numeric_limits<Real>::infinity();
  std::uint32_t best_t = kNoTriangle;
  TriangleClosestPoint best_c;
  tree_.nearest(p, best, [&](std::uint32_t t, Real& best_sq) {
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
