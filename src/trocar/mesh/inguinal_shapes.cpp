// Shape builders for the TAPP groin: tubes along centrelines, a wall grid with a round hole, and
// the hernia sac (inguinal_anatomy.h, inguinal_parts.h).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "trocar/core/error.h"
#include "trocar/mesh/inguinal_anatomy.h"
#include "trocar/mesh/inguinal_parts.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

/// A unit vector perpendicular to t (t unit).
Vec3 any_perpendicular(const Vec3& t) {
  const Vec3 helper = std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return t.cross(helper).normalized();
}

}  // namespace

TriMesh make_tube(const std::vector<Vec3>& centreline, Real radius, std::size_t segments) {
  const std::size_t n = centreline.size();
  if (n < 2) throw Error("make_tube: the centreline needs at least 2 points");
  if (!(radius > 0)) throw Error("make_tube: radius must be > 0");
  if (segments < 3) throw Error("make_tube: segments must be >= 3");
  std::vector<Vec3> tangent(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 d = centreline[std::min(k + 1, n - 1)] - centreline[k == 0 ? 0 : k - 1];
    if (!(d.norm() > 0)) throw Error("make_tube: consecutive centreline points must differ");
    tangent[k] = d.normalized();
  }
  TriMesh mesh;
  mesh.positions.reserve(n * segments + 2);
  // Parallel transport (Bishop frame): u is rotated from one tangent to the next by the smallest
  // rotation, so the rings do not twist.
  Vec3 u = any_perpendicular(tangent[0]);
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) {
      u = (u - u.dot(tangent[k]) * tangent[k]);
      u = u.norm() > 1e-9 ? Vec3(u.normalized()) : any_perpendicular(tangent[k]);
    }
    const Vec3 v = tangent[k].cross(u);
    for (std::size_t j = 0; j < segments; ++j) {
      const Real a = 2 * kPi * static_cast<Real>(j) / static_cast<Real>(segments);
      mesh.positions.push_back(centreline[k] + radius * (std::cos(a) * u + std::sin(a) * v));
    }
  }
  const auto at = [&](std::size_t k, std::size_t j) { return static_cast<std::uint32_t>(k * segments + j % segments); };
  for (std::size_t k = 0; k + 1 < n; ++k)
    for (std::size_t j = 0; j < segments; ++j) {
      mesh.triangles.push_back({at(k, j), at(k, j + 1), at(k + 1, j + 1)});
      mesh.triangles.push_back({at(k, j), at(k + 1, j + 1), at(k + 1, j)});
    }
  const auto start = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.push_back(centreline.front());
  mesh.positions.push_back(centreline.back());
  for (std::size_t j = 0; j < segments; ++j) {
    mesh.triangles.push_back({start, at(0, j + 1), at(0, j)});
    mesh.triangles.push_back({start + 1, at(n - 1, j), at(n - 1, j + 1)});
  }
  return mesh;
}

std::vector<Vec3> smooth_polyline(const std::vector<Vec3>& points, Real spacing) {
  if (points.size() < 2) throw Error("smooth_polyline: needs at least 2 points");
  if (!(spacing > 0)) throw Error("smooth_polyline: spacing must be > 0");
  // Dense uniform Catmull–Rom through the points (end points doubled), then equal arc steps.
  std::vector<Vec3> dense;
  constexpr int kSub = 16;
  const std::size_t n = points.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec3& p0 = points[i == 0 ? 0 : i - 1];
    const Vec3& p1 = points[i];
    const Vec3& p2 = points[i + 1];
    const Vec3& p3 = points[std::min(i + 2, n - 1)];
    for (int s = 0; s < kSub; ++s) {
      const Real t = static_cast<Real>(s) / kSub, t2 = t * t, t3 = t2 * t;
      dense.push_back(0.5 * ((2 * p1) + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 +
                             (-p0 + 3 * p1 - 3 * p2 + p3) * t3));
    }
  }
  dense.push_back(points.back());
  std::vector<Real> s(dense.size(), 0);
  for (std::size_t i = 1; i < dense.size(); ++i) s[i] = s[i - 1] + (dense[i] - dense[i - 1]).norm();
  const Real length = s.back();
  const auto count = static_cast<std::size_t>(std::max<Real>(1, std::ceil(length / spacing)));
  std::vector<Vec3> out;
  std::size_t seg = 0;
  for (std::size_t k = 0; k <= count; ++k) {
    const Real target = length * static_cast<Real>(k) / static_cast<Real>(count);
    while (seg + 2 < dense.size() && s[seg + 1] < target) ++seg;
    const Real span = s[seg + 1] - s[seg];
    const Real f = span > 0 ? std::clamp((target - s[seg]) / span, Real(0), Real(1)) : 0;
    out.push_back(dense[seg] + f * (dense[seg + 1] - dense[seg]));
  }
  out.front() = points.front();
  out.back() = points.back();
  return out;
}

namespace inguinal {

TriMesh make_grid_sheet(const SheetSpec& spec, const HeightField& height, std::vector<std::uint32_t> (&border)[4]) {
  const std::size_t nx = spec.nx, ny = spec.ny, m = spec.hole_m;
  const bool hole = m > 0;
  if (hole && (spec.hole_i < m + 1 || spec.hole_i + m + 1 > nx || spec.hole_j < m + 1 || spec.hole_j + m + 1 > ny))
    throw Error("make_grid_sheet: the hole's square must lie inside the sheet with a cell to spare");
  if (hole && !(spec.hole_r > 0 && spec.hole_r < static_cast<Real>(m) * spec.cell * 0.9))
    throw Error("make_grid_sheet: the hole radius must be > 0 and < 0.9 of the square's half-size");
  const auto inside_square = [&](std::size_t i, std::size_t j) {
    const auto di = static_cast<long>(i) - static_cast<long>(spec.hole_i);
    const auto dj = static_cast<long>(j) - static_cast<long>(spec.hole_j);
    return hole && std::labs(di) < static_cast<long>(m) && std::labs(dj) < static_cast<long>(m);
  };
  TriMesh mesh;
  std::vector<std::int64_t> node((nx + 1) * (ny + 1), -1);
  const auto point = [&](Real x, Real y) { return Vec3(x, y, height(x, y)); };
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i <= nx; ++i) {
      if (inside_square(i, j)) continue;
      node[j * (nx + 1) + i] = static_cast<std::int64_t>(mesh.positions.size());
      const Real x = spec.x0 + spec.cell * static_cast<Real>(i), y = spec.y0 + spec.cell * static_cast<Real>(j);
      mesh.positions.push_back(point(x, y));
      if (j == 0) border[0].push_back(static_cast<std::uint32_t>(mesh.positions.size() - 1));
      if (i == nx) border[1].push_back(static_cast<std::uint32_t>(mesh.positions.size() - 1));
      if (j == ny) border[2].push_back(static_cast<std::uint32_t>(mesh.positions.size() - 1));
      if (i == 0) border[3].push_back(static_cast<std::uint32_t>(mesh.positions.size() - 1));
    }
  const auto id = [&](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(node[j * (nx + 1) + i]); };
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      if (hole && i + m >= spec.hole_i && i < spec.hole_i + m && j + m >= spec.hole_j && j < spec.hole_j + m) continue;
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      } else {
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({b, c, d});
      }
    }
  if (!hole) return mesh;
  // The square's border nodes counter-clockwise from its lower right corner.
  std::vector<std::pair<std::size_t, std::size_t>> ring;
  const std::size_t il = spec.hole_i - m, ir = spec.hole_i + m, jb = spec.hole_j - m, jt = spec.hole_j + m;
  for (std::size_t t = 0; t < 2 * m; ++t) ring.emplace_back(ir, jb + t);
  for (std::size_t t = 0; t < 2 * m; ++t) ring.emplace_back(ir - t, jt);
  for (std::size_t t = 0; t < 2 * m; ++t) ring.emplace_back(il, jt - t);
  for (std::size_t t = 0; t < 2 * m; ++t) ring.emplace_back(il + t, jb);
  const std::size_t s = ring.size(), bands = std::max<std::size_t>(1, spec.hole_rings);
  const Real cx = spec.x0 + spec.cell * static_cast<Real>(spec.hole_i);
  const Real cy = spec.y0 + spec.cell * static_cast<Real>(spec.hole_j);
  std::vector<std::uint32_t> rings((bands + 1) * s);
  for (std::size_t j = 0; j < s; ++j) {
    const Real sx = spec.x0 + spec.cell * static_cast<Real>(ring[j].first);
    const Real sy = spec.y0 + spec.cell * static_cast<Real>(ring[j].second);
    const Vec2 dir = Vec2(sx - cx, sy - cy).normalized();
    for (std::size_t k = 0; k < bands; ++k) {
      const Real f = static_cast<Real>(k) / static_cast<Real>(bands);
      const Real x = (1 - f) * (cx + spec.hole_r * dir.x()) + f * sx;
      const Real y = (1 - f) * (cy + spec.hole_r * dir.y()) + f * sy;
      rings[k * s + j] = static_cast<std::uint32_t>(mesh.positions.size());
      mesh.positions.push_back(point(x, y));
    }
    rings[bands * s + j] = id(ring[j].first, ring[j].second);
  }
  for (std::size_t k = 0; k < bands; ++k)
    for (std::size_t j = 0; j < s; ++j) {
      const std::size_t jn = (j + 1) % s;
      const std::uint32_t a = rings[k * s + j], b = rings[(k + 1) * s + j], c = rings[(k + 1) * s + jn],
                          d = rings[k * s + jn];
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  return mesh;
}

TriMesh make_sac(const Vec3& centre, const Vec3& normal, const Vec3& e1, const Vec3& axis, Real neck_r, Real cap,
                 Real length, std::size_t segments, std::size_t rings, std::vector<std::uint32_t>& neck) {
  if (segments < 8 || rings < 2) throw Error("make_sac: needs segments >= 8 and rings >= 2");
  if (!(neck_r > 0 && cap > 0 && length > 0)) throw Error("make_sac: sizes must be > 0");
  const Vec3 e2 = normal.cross(e1);
  const Real depth_per_axis = -axis.dot(normal);  // depth below the wall per unit along the axis
  if (!(depth_per_axis > 0.3)) throw Error("make_sac: the axis must point out of the cavity");
  // Profile from the cavity-side pole to the outer pole: (height above the wall plane, radius,
  // centre offset along the axis). Cap rings: a spherical-cap-like dome; outer rings: the
  // half-ellipsoid ρ = R·cos β, depth = L·sin β.
  struct Ring {
    Real h, r;
  };
  std::vector<Ring> profile;
  constexpr std::size_t kCapRings = 2;
  for (std::size_t k = 1; k <= kCapRings; ++k) {
    const Real b = 0.5 * kPi * static_cast<Real>(k) / static_cast<Real>(kCapRings + 1);
    profile.push_back({cap * std::cos(b), neck_r * std::sin(b)});
  }
  const std::size_t neck_index = profile.size();
  profile.push_back({0, neck_r});
  for (std::size_t k = 1; k < rings; ++k) {
    const Real b = 0.5 * kPi * static_cast<Real>(k) / static_cast<Real>(rings);
    profile.push_back({-length * std::sin(b), neck_r * std::cos(b)});
  }
  TriMesh mesh;
  mesh.positions.push_back(centre + cap * normal);  // cavity-side pole
  for (std::size_t k = 0; k < profile.size(); ++k) {
    // Rings outside the wall slide along the (tilted) axis; the cap and the neck stay round the
    // normal, so the neck lies in the wall's plane.
    const Real depth = -profile[k].h;
    const Vec3 c = depth > 0 ? Vec3(centre + (depth / depth_per_axis) * axis) : Vec3(centre + profile[k].h * normal);
    for (std::size_t j = 0; j < segments; ++j) {
      const Real a = 2 * kPi * static_cast<Real>(j) / static_cast<Real>(segments);
      if (k == neck_index) neck.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      mesh.positions.push_back(c + profile[k].r * (std::cos(a) * e1 + std::sin(a) * e2));
    }
  }
  const Vec3 last = centre + (length / depth_per_axis) * axis;
  mesh.positions.push_back(last);
  const auto ring_at = [&](std::size_t k, std::size_t j) {
    return static_cast<std::uint32_t>(1 + k * segments + j % segments);
  };
  // Seen from the cavity (+normal), angles increase counter-clockwise (e1 → e2), so the top fan
  // is (pole, j, j+1) and the sides go from ring k (nearer the cavity) to k + 1.
  for (std::size_t j = 0; j < segments; ++j) mesh.triangles.push_back({0, ring_at(0, j), ring_at(0, j + 1)});
  for (std::size_t k = 0; k + 1 < profile.size(); ++k)
    for (std::size_t j = 0; j < segments; ++j) {
      mesh.triangles.push_back({ring_at(k, j), ring_at(k + 1, j), ring_at(k + 1, j + 1)});
      mesh.triangles.push_back({ring_at(k, j), ring_at(k + 1, j + 1), ring_at(k, j + 1)});
    }
  const auto bottom = static_cast<std::uint32_t>(mesh.positions.size() - 1);
  const std::size_t kl = profile.size() - 1;
  for (std::size_t j = 0; j < segments; ++j) mesh.triangles.push_back({bottom, ring_at(kl, j + 1), ring_at(kl, j)});
  return mesh;
}

}  // namespace inguinal
}  // namespace trocar
