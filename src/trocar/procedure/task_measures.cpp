#include "trocar/procedure/task_measures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "trocar/core/pose.h"

namespace trocar {
namespace {

Real cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Distance from p to segment ab in the plane.
Real segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const Real len2 = ab.squaredNorm();
  const Real t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, Real(0), Real(1)) : Real(0);
  return (a + t * ab - p).norm();
}

/// Crossing-number test of p against a closed polygon.
bool inside_polygon(const Vec2& p, std::span<const Vec2> poly) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

}  // namespace

AreaSplit area_beyond_plane(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                            const WallPlane& plane) {
  AreaSplit split;
  for (const Triangle& t : triangles) {
    const std::array<Vec3, 3> x = {positions[t[0]], positions[t[1]], positions[t[2]]};
    const Real area = 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
    split.total += area;
    std::array<Real, 3> d{};
    for (int k = 0; k < 3; ++k) d[k] = (x[k] - plane.point).dot(plane.normal);
    if (d[0] >= 0 && d[1] >= 0 && d[2] >= 0) {
      split.beyond += area;
      continue;
    }
    if (d[0] <= 0 && d[1] <= 0 && d[2] <= 0) continue;
    // Clip the triangle to d ≥ 0 (Sutherland–Hodgman with one plane: at most 4 corners), then
    // the polygon's area is half the norm of Σ corner × next corner (planar polygon).
    std::array<Vec3, 4> poly;
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const int j = (k + 1) % 3;
      if (d[k] >= 0) poly[n++] = x[k];
      if ((d[k] > 0 && d[j] < 0) || (d[k] < 0 && d[j] > 0)) poly[n++] = x[k] + (d[k] / (d[k] - d[j])) * (x[j] - x[k]);
    }
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < n; ++k) sum += (poly[k] - poly[0]).cross(poly[(k + 1) % n] - poly[0]);
    split.beyond += 0.5 * sum.norm();
  }
  return split;
}

Real flipped_area(std::span<const Vec3> positions, std::span<const Triangle> triangles, const Vec3& normal) {
  Real projected = 0;  // Σ area·(nₜ·normal) = Σ ½ (cross·normal)
  for (const Triangle& t : triangles)
    projected += 0.5 * (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).dot(normal);
  const Real side = projected >= 0 ? 1.0 : -1.0;
  Real flipped = 0;
  for (const Triangle& t : triangles) {
    const Vec3 c = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    if (side * c.dot(normal) < 0) flipped += 0.5 * c.norm();
  }
  return flipped;
}

CoverageRegion::CoverageRegion(const WallPlane& plane, std::span<const Vec3> polygon, const Vec3& centre, Real radius,
                               Real spacing)
    : plane_(plane), spacing_(spacing > 0 ? spacing : 0.0025) {
  const Real len = plane_.normal.norm();
  plane_.normal = len > 0 ? Vec3(plane_.normal / len) : Vec3(0, 0, 1);
  u_ = orthogonal_towards(plane_.normal, Vec3::UnitX());
  v_ = plane_.normal.cross(u_);
  std::vector<Vec2> poly;
  if (polygon.size() >= 3)
    for (const Vec3& p : polygon) poly.push_back(to_plane(p));
  const Vec2 c = to_plane(centre);
  Vec2 lo = Vec2::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const Vec2& p : poly) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (radius > 0) {
    lo = lo.cwiseMin(c - Vec2::Constant(radius));
    hi = hi.cwiseMax(c + Vec2::Constant(radius));
  }
  if (!(lo.x() <= hi.x())) return;  // nothing required
  origin_ = lo;
  nx_ = static_cast<std::size_t>(std::floor((hi.x() - lo.x()) / spacing_)) + 1;
  ny_ = static_cast<std::size_t>(std::floor((hi.y() - lo.y()) / spacing_)) + 1;
  required_.assign(nx_ * ny_, 0);
  covered_.assign(nx_ * ny_, 0);
  for (std::size_t j = 0; j < ny_; ++j)
    for (std::size_t i = 0; i < nx_; ++i) {
      const Vec2 p = origin_ + spacing_ * Vec2(static_cast<Real>(i), static_cast<Real>(j));
      bool need = radius > 0 && (p - c).norm() <= radius;
      if (!need && !poly.empty()) {
        need = inside_polygon(p, poly);
        for (std::size_t k = 0; !need && k < poly.size(); ++k)
          need = segment_distance(p, poly[k], poly[(k + 1) % poly.size()]) <= 1e-12;
      }
      required_[j * nx_ + i] = need ? 1 : 0;
      required_count_ += need ? 1 : 0;
    }
}

Vec2 CoverageRegion::to_plane(const Vec3& p) const {
  const Vec3 d = p - plane_.point;
  return {d.dot(u_), d.dot(v_)};
}

Real CoverageRegion::covered_fraction(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  if (required_count_ == 0) return 1;
  std::fill(covered_.begin(), covered_.end(), std::uint8_t{0});
  const Real eps = 1e-9 * spacing_;
  for (const Triangle& t : triangles) {
    const Vec2 a = to_plane(positions[t[0]]), b = to_plane(positions[t[1]]), c = to_plane(positions[t[2]]);
    const Real area2 = cross2(b - a, c - a);
    if (std::abs(area2) <= eps * eps) continue;  // seen edge-on: covers nothing
    const Vec2 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const auto first = [&](Real x, Real o) { return static_cast<long>(std::ceil((x - o) / spacing_ - 1e-9)); };
    const auto last = [&](Real x, Real o) { return static_cast<long>(std::floor((x - o) / spacing_ + 1e-9)); };
    const long i0 = std::max(0L, first(lo.x(), origin_.x()));
    const long i1 = std::min(static_cast<long>(nx_) - 1, last(hi.x(), origin_.x()));
    const long j0 = std::max(0L, first(lo.y(), origin_.y()));
    const long j1 = std::min(static_cast<long>(ny_) - 1, last(hi.y(), origin_.y()));
    const Real s = area2 > 0 ? 1.0 : -1.0;
    const Real tol = -1e-9 * std::abs(area2);
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * nx_ + static_cast<std::size_t>(i);
        if (!required_[k] || covered_[k]) continue;
        const Vec2 p = origin_ + spacing_ * Vec2(static_cast<Real>(i), static_cast<Real>(j));
        if (s * cross2(b - a, p - a) >= tol && s * cross2(c - b, p - b) >= tol && s * cross2(a - c, p - c) >= tol)
          covered_[k] = 1;
      }
  }
  std::size_t n = 0;
  for (std::size_t k = 0; k < covered_.size(); ++k) n += covered_[k];
  return static_cast<Real>(n) / static_cast<Real>(required_count_);
}

}  // namespace trocar
