#include "trocar/mesh/prosthetic_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

/// Arc length of the spiral r = b·φ from φ = 0 (b = gap/2π): (b/2)[φ√(1+φ²) + asinh φ].
Real spiral_length(Real b, Real phi) { return 0.5 * b * (phi * std::sqrt(1 + phi * phi) + std::asinh(phi)); }

}  // namespace

TriMesh make_prosthetic_mesh(Real width, Real height, Real spacing) {
  if (!(width > 0 && height > 0 && spacing > 0) || !std::isfinite(width) || !std::isfinite(height) ||
      !std::isfinite(spacing))
    throw Error("prosthetic mesh: width, height and spacing must be positive and finite");
  const Real nxr = std::max<Real>(1, std::round(width / spacing)), nyr = std::max<Real>(1, std::round(height / spacing));
  if ((nxr + 1) * (nyr + 1) > 1e6) throw Error("prosthetic mesh: more than 10^6 vertices (spacing too small)");
  TriMesh mesh = make_sheet(width, height, static_cast<std::size_t>(nxr), static_cast<std::size_t>(nyr));
  mesh.texcoords.reserve(3 * mesh.triangles.size());
  for (const Triangle& t : mesh.triangles)
    for (const std::uint32_t v : t)
      mesh.texcoords.emplace_back(mesh.positions[v].x() + width / 2, mesh.positions[v].y() + height / 2);
  return mesh;
}

void roll_sheet(std::span<Vec3> positions, const SheetRoll& roll) {
  if (roll.axis != 0 && roll.axis != 1) throw Error("roll: the axis must be x or y");
  if (!(roll.radius > 0 && roll.gap > 0) || !std::isfinite(roll.radius) || !std::isfinite(roll.gap))
    throw Error("roll: radius and gap must be positive and finite");
  if (positions.empty()) return;
  Vec3 lo = positions.front(), hi = lo;
  for (const Vec3& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (hi.z() - lo.z() > 1e-6 * std::max<Real>((hi - lo).norm(), 1e-9))
    throw Error("roll: the sheet must be flat in a plane z = const");
  const int across = roll.axis == 0 ? 1 : 0;  // the coordinate that becomes arc length
  const Real b = roll.gap / (2 * kPi);
  const Real phi0 = roll.radius / b;
  const Real length0 = spiral_length(b, phi0);
  const auto angle_at = [&](Real s) {  // θ with arc length s from the inner end (Newton)
    Real theta = s / roll.radius;
    for (int k = 0; k < 50; ++k) {
      const Real phi = phi0 + theta;
      const Real f = spiral_length(b, phi) - length0 - s;
      theta -= f / (b * std::sqrt(1 + phi * phi));  // dL/dθ = √(r² + b²) = b√(1 + φ²)
      if (std::abs(f) < 1e-13) break;
    }
    return theta;
  };
  const Real theta_end = angle_at(hi[across] - lo[across]);
  const Real outer = roll.radius + b * theta_end;
  // The outer end points straight down, so the roll rests on the plane at its lowest point.
  const Real theta0 = -kPi / 2 - theta_end;
  Vec3 centre = 0.5 * (lo + hi);
  centre.z() = lo.z() + outer;
  for (Vec3& p : positions) {
    const Real theta = angle_at(p[across] - lo[across]);
    const Real r = roll.radius + b * theta;
    p[across] = centre[across] + r * std::cos(theta + theta0);
    p.z() = centre.z() + r * std::sin(theta + theta0);
  }
}

}  // namespace trocar
