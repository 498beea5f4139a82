#include "trocar/electrosurgery/electrode.h"

#include <algorithm>
#include <limits>

#include "trocar/geometry/closest_point.h"

namespace trocar {

std::vector<std::uint32_t> electrode_vertices(std::span<const Vec3> positions, const Vec3& shaft, Real active_length) {
  std::vector<std::uint32_t> out;
  if (positions.empty()) return out;
  Real tip = std::numeric_limits<Real>::infinity();
  for (const Vec3& p : positions) tip = std::min(tip, shaft.dot(p));
  for (std::uint32_t v = 0; v < positions.size(); ++v)
    if (shaft.dot(positions[v]) - tip <= active_length) out.push_back(v);
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
