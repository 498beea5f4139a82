#include "trocar/mesh/instruments.h"

#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

void require(bool ok, const char* what) {
  if (!ok) throw Error(std::string("instrument generator: ") + what);
}

bool positive(Real x) { return x > 0 && std::isfinite(x); }

std::uint32_t u32(std::size_t i) { return static_cast<std::uint32_t>(i); }

/// Appends `part` to `mesh` (indices shifted).
void append(TriMesh& mesh, const TriMesh& part) {
  const std::uint32_t base = u32(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  for (const Triangle& t : part.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

/// Reverses every triangle when the closed mesh's signed volume is negative (outward after).
void orient_outward(TriMesh& mesh) {
  if (mesh.signed_volume() >= 0) return;
  for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
}

/// A box whose z = 0 face is the rectangle [x0, x1] × [y0, y1] shrunk about its centre by
/// `tip_scale` and whose z = length face is the full rectangle. 8 V, 12 T, outward.
TriMesh tapered_box(Real x0, Real x1, Real y0, Real y1, Real length, Real tip_scale) {
  TriMesh box = make_box(1, 1, 1);  // corners ±0.5, the same triangles
  const Real cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  for (Vec3& p : box.positions) {
    const Real s = p.z() < 0 ? tip_scale : 1;  // the −z face becomes the tip at z = 0
    p = Vec3(cx + s * p.x() * (x1 - x0), cy + s * p.y() * (y1 - y0), (p.z() + 0.5) * length);
  }
  return box;
}

}  // namespace

InstrumentMesh make_grasper(const GrasperSize& size) {
  require(positive(size.shaft_radius) && positive(size.shaft_length), "grasper shaft sizes must be positive");
  require(positive(size.jaw_length) && positive(size.jaw_width) && positive(size.jaw_thickness),
          "grasper jaw sizes must be positive");
  require(size.jaw_gap >= 0 && std::isfinite(size.jaw_gap), "grasper jaw gap must be >= 0");
  require(size.segments >= 3, "grasper needs segments >= 3");
  InstrumentMesh out;
  const Real hw = size.jaw_width / 2, g = size.jaw_gap / 2, t = size.jaw_thickness;
  constexpr Real kTip = 2.0 / 3.0;
  // The jaws' centres sit at y = ±(g + t/2); the taper shrinks about those centres, so the
  // grasping faces lie at |y| = g + t/2·(1 − kTip) at the tip and g at the base.
  append(out.mesh, tapered_box(-hw, hw, g, g + t, size.jaw_length, kTip));
  append(out.mesh, tapered_box(-hw, hw, -g - t, -g, size.jaw_length, kTip));
  for (std::uint32_t i = 0; i < 24; ++i) out.jaw_triangles.push_back(i);
  TriMesh shaft = make_cylinder(size.shaft_radius, size.shaft_length, size.segments, true);
  for (Vec3& p : shaft.positions) p.z() += size.jaw_length;
  append(out.mesh, shaft);
  return out;
}

namespace {

/// Closes a stack of `rings` rings of `s` vertices each (positions 0 … rings·s − 1, in order),
/// followed by the centres of its first and last cap: a band of triangles between consecutive
/// rings and a fan on each end, then outward orientation. The hook's and the tacker's bodies.
void close_ring_stack(TriMesh& m, std::size_t rings, std::size_t s) {
  const std::size_t first_centre = rings * s;
  for (std::size_t k = 0; k + 1 < rings; ++k)
    for (std::size_t i = 0; i < s; ++i) {
      const std::size_t j = (i + 1) % s, lo = k * s, hi = (k + 1) * s;
      m.triangles.push_back({u32(lo + i), u32(lo + j), u32(hi + j)});
      m.triangles.push_back({u32(lo + i), u32(hi + j), u32(hi + i)});
    }
  for (std::size_t i = 0; i < s; ++i) {
    const std::size_t j = (i + 1) % s;
    m.triangles.push_back({u32(first_centre), u32(j), u32(i)});
    m.triangles.push_back({u32(first_centre + 1), u32(first_centre - s + i), u32(first_centre - s + j)});
  }
  orient_outward(m);
}

/// A closed solid of revolution about z: one ring of `s` vertices per (radius, z) of `profile`
/// (tip end first), each end capped at its centre on the axis (close_ring_stack). The tacker's and
/// the suction-irrigator's blunt shafts; tip at the origin, tip_axis −z.
InstrumentMesh revolved_shaft(std::span<const std::array<Real, 2>> profile, std::size_t s) {
  InstrumentMesh out;
  TriMesh& m = out.mesh;
  for (const auto& ring : profile)
    for (std::size_t i = 0; i < s; ++i) {
      const Real a = 2 * kPi * static_cast<Real>(i) / static_cast<Real>(s);
      m.positions.emplace_back(ring[0] * std::cos(a), ring[0] * std::sin(a), ring[1]);
    }
  m.positions.emplace_back(0, 0, profile.front()[1]);  // the tip's cap centre, then the handle's
  m.positions.emplace_back(0, 0, profile.back()[1]);
  close_ring_stack(m, profile.size(), s);
  out.tip = Vec3::Zero();
  out.tip_axis = -Vec3::UnitZ();
  return out;
}

}  // namespace

InstrumentMesh make_hook_probe(const HookSize& size) {
  require(positive(size.shaft_radius) && positive(size.shaft_length), "hook shaft sizes must be positive");
  require(positive(size.hook_radius) && size.hook_radius < size.shaft_radius, "hook wire radius must be in (0, shaft radius)");
  require(size.stem_length > 2 * size.hook_radius && std::isfinite(size.stem_length), "hook stem must be longer than the wire's diameter");
  require(size.hook_length > size.hook_radius && std::isfinite(size.hook_length), "hook foot must be longer than the wire's radius");
  require(size.segments >= 3, "hook needs segments >= 3");
  const std::size_t s = size.segments;
  const Real r = size.hook_radius, R = size.shaft_radius;
  const Real top = size.stem_length + size.shaft_length;
  InstrumentMesh out;
  TriMesh& m = out.mesh;
  // The elbow's axis point is C = (0, 0, r). Around the stem (axis z) a point at angle φ is
  // (r cos φ, r sin φ); on the mitre plane (normal ∝ (1, 0, −1)) its height is r + r cos φ,
  // which is also at distance r from the foot's axis (the x axis at z = r).
  for (std::size_t i = 0; i < s; ++i) {  // ring 0: the foot's end, a circle in the plane x = L
    const Real a = 2 * kPi * static_cast<Real>(i) / static_cast<Real>(s);
    m.positions.emplace_back(size.hook_length, r * std::sin(a), r + r * std::cos(a));
  }
  for (std::size_t i = 0; i < s; ++i) {  // ring 1: the elbow
    const Real a = 2 * kPi * static_cast<Real>(i) / static_cast<Real>(s);
    m.positions.emplace_back(r * std::cos(a), r * std::sin(a), r + r * std::cos(a));
  }
  const Real rings[3][2] = {{r, size.stem_length}, {R, size.stem_length}, {R, top}};
  for (const auto& ring : rings)  // rings 2..4: stem top, shaft bottom, shaft top
    for (std::size_t i = 0; i < s; ++i) {
      const Real a = 2 * kPi * static_cast<Real>(i) / static_cast<Real>(s);
      m.positions.emplace_back(ring[0] * std::cos(a), ring[0] * std::sin(a), ring[1]);
    }
  m.positions.emplace_back(size.hook_length, 0, r);  // the foot's cap centre, then the shaft's
  m.positions.emplace_back(0, 0, top);
  close_ring_stack(m, 5, s);
  return out;
}

InstrumentMesh make_tacker(const TackerSize& size) {
  require(positive(size.shaft_radius) && positive(size.shaft_length), "tacker shaft sizes must be positive");
  require(positive(size.bevel) && size.bevel < size.shaft_radius && size.bevel < size.shaft_length,
          "tacker bevel must be in (0, min(shaft radius, shaft length))");
  require(size.segments >= 3, "tacker needs segments >= 3");
  const std::array<Real, 2> rings[3] = {{size.shaft_radius - size.bevel, 0}, {size.shaft_radius, size.bevel},
                                        {size.shaft_radius, size.shaft_length}};
  return revolved_shaft(rings, size.segments);
}

InstrumentMesh make_suction_irrigator(const SuctionIrrigatorSize& size) {
  require(positive(size.shaft_radius) && positive(size.shaft_length), "suction-irrigator shaft sizes must be positive");
  require(positive(size.tip_round) && size.tip_round < size.shaft_radius && size.tip_round < size.shaft_length,
          "suction-irrigator tip_round must be in (0, min(shaft radius, shaft length))");
  require(size.segments >= 3, "suction-irrigator needs segments >= 3");
  require(size.round_rings >= 1, "suction-irrigator needs round_rings >= 1");
  // The tip's edge a quarter circle of radius ρ about (R − ρ, ρ): at θ = 0 the flat disc's rim,
  // at θ = π/2 the full shaft, θ in round_rings equal steps between.
  const Real R = size.shaft_radius, rho = size.tip_round;
  std::vector<std::array<Real, 2>> rings = {{R - rho, 0}};
  for (std::size_t k = 1; k <= size.round_rings; ++k) {
    const Real t = kPi / 2 * static_cast<Real>(k) / static_cast<Real>(size.round_rings);
    rings.push_back({R - rho + rho * std::sin(t), rho - rho * std::cos(t)});
  }
  rings.back() = {R, rho};  // exactly the shaft, whatever sin(π/2) rounds to
  rings.push_back({R, size.shaft_length});
  return revolved_shaft(rings, size.segments);
}

}  // namespace trocar
