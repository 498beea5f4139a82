#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trocar/core/error.h"
#include "trocar/mesh/instruments.h"
#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

TEST(Instruments, GrasperCountsJawsAndSizes) {
  const GrasperSize size;
  const InstrumentMesh g = make_grasper(size);
  const std::size_t s = size.segments;
  EXPECT_EQ(g.mesh.positions.size(), 16 + 2 * s + 2);
  EXPECT_EQ(g.mesh.triangles.size(), 24 + 4 * s);
  const MeshReport r = validate(g.mesh);
  EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.components, 3u);
  EXPECT_EQ(r.euler_characteristic, 6);
  ASSERT_EQ(g.jaw_triangles.size(), 24u);
  for (std::uint32_t t : g.jaw_triangles) {
    ASSERT_LT(t, g.mesh.triangles.size());
    for (int k = 0; k < 3; ++k) EXPECT_LE(g.mesh.positions[g.mesh.triangles[t][k]].z(), size.jaw_length + 1e-15);
  }
  // Tip at the origin, shaft along +z: z ∈ [0, jaw + shaft], Ø5 mm.
  EXPECT_EQ(r.bounds.min.z(), 0.0);
  EXPECT_NEAR(r.bounds.max.z(), 0.32, 1e-15);
  EXPECT_NEAR(r.bounds.max.x(), 0.0025, 1e-15);
  // Jaw grasping faces at y = ±gap/2 at the base: no vertex of the jaws inside the gap.
  for (std::size_t v = 0; v < 16; ++v) EXPECT_GE(std::abs(g.mesh.positions[v].y()), size.jaw_gap / 2 - 1e-15);
  // Volume: two frusta-like boxes and the shaft's prism ½·s·r²·sin(2π/s)·L.
  const Real shaft = 0.5 * static_cast<Real>(s) * 0.0025 * 0.0025 * std::sin(2 * std::numbers::pi / static_cast<Real>(s)) * 0.30;
  const Real base = size.jaw_width * size.jaw_thickness, tip = base * 4.0 / 9.0;
  // A prismatoid with similar end faces: V = L/3·(A₁ + A₂ + √(A₁A₂)).
  const Real jaw = size.jaw_length / 3 * (base + tip + std::sqrt(base * tip));
  EXPECT_NEAR(r.signed_volume, shaft + 2 * jaw, 1e-15);
}

TEST(Instruments, HookProbeOneClosedTube) {
  const HookSize size;
  const InstrumentMesh h = make_hook_probe(size);
  const std::size_t s = size.segments;
  EXPECT_TRUE(h.jaw_triangles.empty());
  EXPECT_EQ(h.mesh.positions.size(), 5 * s + 2);
  EXPECT_EQ(h.mesh.triangles.size(), 10 * s);
  const MeshReport r = validate(h.mesh);
  EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  // The elbow's outer bottom at the origin; the foot out to +x; shaft Ø4.5 mm up +z.
  EXPECT_NEAR(r.bounds.min.z(), 0.0, 1e-18);
  EXPECT_NEAR(r.bounds.max.x(), size.hook_length, 1e-15);
  EXPECT_NEAR(r.bounds.min.x(), -size.shaft_radius, 1e-15);
  EXPECT_NEAR(r.bounds.max.z(), size.stem_length + size.shaft_length, 1e-15);
  // Volume ≈ the shaft's prism plus the wire (stem + foot), the wire within its mitre error.
  const Real sn = std::sin(2 * std::numbers::pi / static_cast<Real>(s)) * 0.5 * static_cast<Real>(s);
  const Real shaft = sn * size.shaft_radius * size.shaft_radius * size.shaft_length;
  const Real wire = sn * size.hook_radius * size.hook_radius * (size.stem_length + size.hook_length);
  EXPECT_NEAR(r.signed_volume, shaft + wire, 0.05 * wire);
}

TEST(Instruments, TackerBluntFiveMillimetreShaft) {
  const TackerSize size;
  const InstrumentMesh t = make_tacker(size);
  const std::size_t s = size.segments;
  EXPECT_TRUE(t.jaw_triangles.empty());
  EXPECT_EQ(t.mesh.positions.size(), 3 * s + 2);
  EXPECT_EQ(t.mesh.triangles.size(), 6 * s);
  const MeshReport r = validate(t.mesh);
  EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  // The grasper's convention: tip at the origin, shaft up +z; Ø5 mm, 33 cm like a ProTack.
  EXPECT_EQ(r.bounds.min.z(), 0.0);
  EXPECT_NEAR(r.bounds.max.z(), 0.33, 1e-15);
  EXPECT_NEAR(r.bounds.max.x(), 0.0025, 1e-15);
  EXPECT_EQ(t.tip, Vec3::Zero());
  EXPECT_EQ(t.tip_axis, Vec3(0, 0, -1));
  // Blunt: the lowest ring is a flat disc of radius 1.5 mm, no point below or at a sharp apex.
  Real tip_disc = 0;
  for (const Vec3& p : t.mesh.positions)
    if (p.z() == 0) tip_disc = std::max(tip_disc, std::hypot(p.x(), p.y()));
  EXPECT_NEAR(tip_disc, size.shaft_radius - size.bevel, 1e-15);
  // Outward and closed: the volume is the prism of the shaft less the chamfer's frustum deficit,
  // ½·s·sin(2π/s)·(R²(L − b) + b/3·(R² + r² + R·r)) with r = R − b.
  const Real sn = 0.5 * static_cast<Real>(s) * std::sin(2 * std::numbers::pi / static_cast<Real>(s));
  const Real R = size.shaft_radius, b = size.bevel, rr = R - b;
  EXPECT_NEAR(r.signed_volume, sn * (R * R * (size.shaft_length - b) + b / 3 * (R * R + rr * rr + R * rr)), 1e-15);
  // Every triangle's normal points away from the axis or out through a cap.
  for (const Triangle& tri : t.mesh.triangles) {
    const Vec3 a = t.mesh.positions[tri[0]], b2 = t.mesh.positions[tri[1]], c = t.mesh.positions[tri[2]];
    const Vec3 n = (b2 - a).cross(c - a);
    const Vec3 centre = (a + b2 + c) / 3;
    const Vec3 out = centre - Vec3(0, 0, std::clamp(centre.z(), 0.01, 0.32));
    EXPECT_GT(n.dot(out), 0);
  }
}

TEST(Instruments, SuctionIrrigatorRoundedFiveMillimetreCannula) {
  const SuctionIrrigatorSize size;
  const InstrumentMesh c = make_suction_irrigator(size);
  const std::size_t s = size.segments, n = size.round_rings;
  EXPECT_TRUE(c.jaw_triangles.empty());
  EXPECT_EQ(c.mesh.positions.size(), (n + 2) * s + 2);  // 3 rings on the rounding: 82
  EXPECT_EQ(c.mesh.triangles.size(), 2 * (n + 2) * s);  // 160
  const MeshReport r = validate(c.mesh);
  EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  // Tip at the origin, shaft up +z; Ø5 mm, 33 cm.
  EXPECT_EQ(r.bounds.min.z(), 0.0);
  EXPECT_NEAR(r.bounds.max.z(), 0.33, 1e-15);
  EXPECT_NEAR(r.bounds.max.x(), 0.0025, 1e-15);
  EXPECT_EQ(c.tip, Vec3::Zero());
  EXPECT_EQ(c.tip_axis, Vec3(0, 0, -1));
  // Rounded: every vertex of the tip's rings lies on the quarter circle of radius 1 mm about the
  // point 1.5 mm out and 1 mm up (the torus of the fillet), the flat disc's rim 1.5 mm out at z = 0.
  const Real R = size.shaft_radius, rho = size.tip_round;
  int on_round = 0;
  for (std::size_t v = 0; v < (n + 1) * s; ++v) {
    const Vec3& p = c.mesh.positions[v];
    EXPECT_NEAR(std::hypot(std::hypot(p.x(), p.y()) - (R - rho), p.z() - rho), rho, 1e-15) << v;
    on_round += p.z() <= rho + 1e-15 ? 1 : 0;
  }
  EXPECT_EQ(on_round, static_cast<int>((n + 1) * s));
  // Volume: the s-gon frusta between consecutive rings (r, z) at θ = kπ/2n on the rounding, then
  // the prism of the shaft: ½·s·sin(2π/s)·Σ h/3·(r₁² + r₂² + r₁r₂).
  const Real sn = 0.5 * static_cast<Real>(s) * std::sin(2 * std::numbers::pi / static_cast<Real>(s));
  Real volume = sn * R * R * (size.shaft_length - rho), r1 = R - rho, z1 = 0;
  for (std::size_t k = 1; k <= n; ++k) {
    const Real t = std::numbers::pi / 2 * static_cast<Real>(k) / static_cast<Real>(n);
    const Real r2 = R - rho + rho * std::sin(t), z2 = rho - rho * std::cos(t);
    volume += sn * (z2 - z1) / 3 * (r1 * r1 + r2 * r2 + r1 * r2);
    r1 = r2, z1 = z2;
  }
  EXPECT_NEAR(r.signed_volume, volume, 1e-15);
  // Between the tacker's chamfer and the full cylinder: more than the chamfered, less than the
  // square-ended one.
  TackerSize chamfered;
  chamfered.bevel = rho;
  EXPECT_GT(r.signed_volume, validate(make_tacker(chamfered).mesh).signed_volume);
  EXPECT_LT(r.signed_volume, sn * R * R * size.shaft_length);
  // One round ring is the tacker's chamfer exactly.
  SuctionIrrigatorSize one = size;
  one.round_rings = 1;
  EXPECT_EQ(make_suction_irrigator(one).mesh.positions, make_tacker(chamfered).mesh.positions);
  // Every triangle's normal points away from the axis or out through a cap.
  for (const Triangle& tri : c.mesh.triangles) {
    const Vec3 a = c.mesh.positions[tri[0]], b = c.mesh.positions[tri[1]], d = c.mesh.positions[tri[2]];
    const Vec3 centre = (a + b + d) / 3;
    const Vec3 out = centre - Vec3(0, 0, std::clamp(centre.z(), 0.01, 0.32));
    EXPECT_GT((b - a).cross(d - a).dot(out), 0);
  }
}

TEST(Instruments, RejectBadSizes) {
  GrasperSize g;
  g.jaw_length = 0;
  EXPECT_THROW(make_grasper(g), Error);
  HookSize h;
  h.hook_radius = h.shaft_radius;
  EXPECT_THROW(make_hook_probe(h), Error);
  TackerSize k;
  k.bevel = k.shaft_radius;
  EXPECT_THROW(make_tacker(k), Error);
  k = TackerSize{};
  k.segments = 2;
  EXPECT_THROW(make_tacker(k), Error);
  SuctionIrrigatorSize c;
  c.tip_round = c.shaft_radius;
  EXPECT_THROW(make_suction_irrigator(c), Error);
  c = SuctionIrrigatorSize{};
  c.round_rings = 0;
  EXPECT_THROW(make_suction_irrigator(c), Error);
  c = SuctionIrrigatorSize{};
  c.shaft_length = -1;
  EXPECT_THROW(make_suction_irrigator(c), Error);
}

}  // namespace
}  // namespace trocar
