#include "trocar/electrosurgery/electrode.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

#include "trocar/geometry/closest_point.h"

namespace trocar {

std::vector<Vec3> electrode_points(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                                   const Vec3& shaft, Real active_length, Real spacing) {
  std::vector<Vec3> out;
  if (positions.empty()) return out;
  Real tip = std::numeric_limits<Real>::infinity();
  for (const Vec3& p : positions) tip = std::min(tip, shaft.dot(p));
  std::vector<std::uint8_t> active(positions.size(), 0);
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (shaft.dot(positions[v]) - tip <= active_length) {
      active[v] = 1;
      out.push_back(positions[v]);
    }
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      if (a < positions.size() && b < positions.size() && active[a] && active[b]) edges.insert(std::minmax(a, b));
    }
  for (const auto& [a, b] : edges) {
    const Real length = (positions[b] - positions[a]).norm();
    const int pieces = spacing > 0 ? static_cast<int>(std::ceil(length / spacing)) : 1;
    for (int k = 1; k < pieces; ++k) out.push_back(positions[a] + (positions[b] - positions[a]) * (Real(k) / pieces));
  }
  return out;
}

Real touch_triangles(std::span<const Vec3> points, std::span<const Vec3> positions, std::span<const Triangle> triangles,
                     std::span<const Real> rest_areas, Real reach, std::span<std::uint8_t> touched) {
  std::fill(touched.begin(), touched.end(), std::uint8_t{0});
  if (points.empty()) return 0;
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= reach;
  hi.array() += reach;
  const Real reach2 = reach * reach;
  Real area = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3& a = positions[triangles[t][0]];
    const Vec3& b = positions[triangles[t][1]];
    const Vec3& c = positions[triangles[t][2]];
    const Vec3 tlo = a.cwiseMin(b).cwiseMin(c), thi = a.cwiseMax(b).cwiseMax(c);
    if ((tlo.array() > hi.array()).any() || (thi.array() < lo.array()).any()) continue;
    for (const Vec3& p : points) {
      if ((p.array() < tlo.array() - reach).any() || (p.array() > thi.array() + reach).any()) continue;
      if ((closest_point_on_triangle(p, a, b, c).point - p).squaredNorm() <= reach2) {
        touched[t] = 1;
        area += rest_areas[t];
        break;
      }
    }
  }
  return area;
}

void share_power(Real power, Real total_area, std::span<const std::uint8_t> touched, std::span<const Real> rest_areas,
                 std::span<Real> out) {
  if (!(power > 0) || !(total_area > 0)) return;
  for (std::size_t t = 0; t < touched.size(); ++t)
    if (touched[t]) out[t] += power * rest_areas[t] / total_area;
}

}  // namespace trocar
