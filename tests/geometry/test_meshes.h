#pragma once
// Small closed meshes made in code for the geometry tests.
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "trocar/core/types.h"

namespace trocar::test {

struct SimpleMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

// Makes every face of a convex mesh around the origin counter-clockwise seen from outside.
inline void orient_outward_convex(SimpleMesh& m) {
  for (Triangle& t : m.triangles) {
    const Vec3& a = m.positions[t[0]];
    const Vec3& b = m.positions[t[1]];
    const Vec3& c = m.positions[t[2]];
    if ((b - a).cross(c - a).dot(a + b + c) < 0) std::swap(t[1], t[2]);
  }
}

// The cube [-h, h]³, two triangles per face.
inline SimpleMesh make_cube(Real h) {
  SimpleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.positions.emplace_back((i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h);
  }
  // Faces as vertex quads (corner ids use bit 0 = x, bit 1 = y, bit 2 = z).
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    const auto u = [&](int k) { return static_cast<std::uint32_t>(q[k]); };
    m.triangles.push_back({u(0), u(1), u(2)});
    m.triangles.push_back({u(0), u(2), u(3)});
  }
  orient_outward_convex(m);
  return m;
}

// Icosahedron subdivided `levels` times and pushed onto the sphere of the given radius:
// 20·4^levels triangles, 10·4^levels + 2 vertices.
inline SimpleMesh make_icosphere(int levels, Real radius) {
  SimpleMesh m;
  const Real g = (1.0 + std::sqrt(5.0)) / 2.0;
  const Real base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (const auto& v : base) m.positions.push_back(Vec3(v[0], v[1], v[2]).normalized());
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    const auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      const auto id = static_cast<std::uint32_t>(m.positions.size() - 1);
      midpoints.emplace(key, id);
      return id;
    };
    std::vector<Triangle> next;
    for (const Triangle& t : m.triangles) {
      const std::uint32_t ab = mid(t[0], t[1]);
      const std::uint32_t bc = mid(t[1], t[2]);
      const std::uint32_t ca = mid(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  for (Vec3& p : m.positions) p *= radius;
  orient_outward_convex(m);
  return m;
}

}  // namespace trocar::test
