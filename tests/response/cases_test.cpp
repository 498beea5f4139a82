// The seed's response case by case (thesis §3.6, Figs. 3.5–3.12), expected values by hand,
// with the depth cap off (kSeed).
//
// Common set-up unless stated: tissue triangle B1 = (0,0,0), B2 = (1,0,0), B3 = (0,1,0) (m).
// n = (B2−B1)×(B3−B1) = (1,0,0)×(0,1,0) = (0,0,1) = n_out, so n_in = (0,0,−1) and the
// barycentric coordinates of a point (x, y, 0) are (1 − x − y, x, y). K = 2000 N/m, μ = 5 N·s/m.
#include <gtest/gtest.h>

#include <cmath>

#include "trocar/geometry/ray_obb.h"
#include "trocar/response/contact_response.h"

namespace trocar {
namespace {

constexpr Real kTol = 1e-12;

// The seed's step 7 verbatim: these cases check its equations, so the simulator's depth cap
// (depth_cap_test.cpp) is off.
const ResponseSettings kSeed = [] {
  ResponseSettings s;
  s.method = ResponseMethod::kObb;  // the seed's kernel (the default is sdf)
  s.depth_cap = false;
  return s;
}();

ContactTriangles tissue_with(const Vec3& a1, const Vec3& a2, const Vec3& a3, const Vec3& v_instrument = Vec3::Zero(),
                             const Vec3& v_tissue = Vec3::Zero()) {
  ContactTriangles t;
  t.a = {a1, a2, a3};
  t.va = {v_instrument, v_instrument, v_instrument};
  t.b = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  t.vb = {v_tissue, v_tissue, v_tissue};
  return t;
}

// Axis-aligned box, centre (0.3, 0.25, 0), half-extents (0.2, 0.1, 0.15): z ∈ [−0.15, 0.15].
Obb straight_box() {
  Obb b;
  b.center = Vec3(0.3, 0.25, 0);
  b.half_extents = Vec3(0.2, 0.1, 0.15);
  return b;
}

void expect_vec(const Vec3& got, const Vec3& want, Real tol = kTol) {
  EXPECT_LT((got - want).norm(), tol) << "got " << got.transpose() << " want " << want.transpose();
}

TEST(ResponseCases, OneVertexThrough_Fig3_5a) {
  // A1 = (0.2,0.2,0.1), A2 = (0.4,0.2,0.1) above; A3 = (0.3,0.3,−0.1) below: d = (0.1, 0.1, −0.1),
  // one vertex inside, no relabelling (A3 is already alone).
  // M on A1A3: t = 0.1/(0.1+0.1) = 0.5 → (0.25, 0.25, 0); N on A2A3: t = 0.5 → (0.35, 0.25, 0).
  // N is inside B: λ = (1 − 0.35 − 0.25, 0.35, 0.25) = (0.4, 0.35, 0.25), so P = N.
  // P in A: s = 1 → (0, 1 − tN, tN) = (0, 0.5, 0.5).
  // OBB: only a3 = z has a3·n_in ≠ 0 (= −1): ray along −z from P (local z = 0) leaves at
  // t = 0.15 → PD = (0, 0, −0.15).
  // Instrument moves at (0,0,−1) m/s, tissue at rest: v̂ = (0,0,−1), PD·v̂ = 0.15, D = (0,0,−0.15).
  // f = K|D| + μ v·n_in = 2000·0.15 + 5·1 = 305 N; F = (0, 0, −305).
  const ContactTriangles t = tissue_with(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1), Vec3(0, 0, -1));
  const ContactResponse r = respond_contact(t, straight_box(), nullptr, {}, kSeed);
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  EXPECT_EQ(r.inside_count, 1);
  EXPECT_EQ(r.lone_vertex, 2);
  EXPECT_FALSE(r.moved_to_edge);
  expect_vec(r.normal_in, Vec3(0, 0, -1));
  expect_vec(r.m, Vec3(0.25, 0.25, 0));
  expect_vec(r.n, Vec3(0.35, 0.25, 0));
  expect_vec(r.point, Vec3(0.35, 0.25, 0));
  expect_vec(r.weights_b, Vec3(0.4, 0.35, 0.25));
  expect_vec(r.weights_a, Vec3(0, 0.5, 0.5));
  expect_vec(r.penetration, Vec3(0, 0, -0.15));
  expect_vec(r.deformation, Vec3(0, 0, -0.15));
  expect_vec(r.relative_velocity, Vec3(0, 0, -1));
  EXPECT_NEAR(r.depth, 0.15, kTol);
  expect_vec(r.force, Vec3(0, 0, -305), 1e-9);
}

TEST(ResponseCases, EdgeThrough_Fig3_5b_RelabelledAsFig3_5c) {
  // Fig. 3.5b: edge A2A3 is inside. A1 = (0.3,0.3,0.1) above; A2 = (0.2,0.2,−0.1),
  // A3 = (0.4,0.2,−0.1) below: d = (0.1, −0.1, −0.1), two inside. Relabel (Fig. 3.5c): the lone
  // vertex (original A1, index 0) becomes A3', and A1' = A2, A2' = A3 (cyclic order kept).
  // M on A1'A3' = A2→A1: t = −0.1/(−0.1 − 0.1) = 0.5 → (0.25, 0.25, 0);
  // N on A2'A3' = A3→A1: t = 0.5 → (0.35, 0.25, 0) = P (inside B).
  // P in the original order: A1 (lone) gets (1−s)tM + s·tN = 0.5, A2 (= A1') gets 0, A3 gets 0.5.
  // Tissue at rest, instrument at rest: resting contact, D = (PD·n_in) n_in = (0, 0, −0.15),
  // f = 2000·0.15 = 300 N.
  const ContactTriangles t = tissue_with(Vec3(0.3, 0.3, 0.1), Vec3(0.2, 0.2, -0.1), Vec3(0.4, 0.2, -0.1));
  const ContactResponse r = respond_contact(t, straight_box(), nullptr, {}, kSeed);
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  EXPECT_EQ(r.inside_count, 2);
  EXPECT_EQ(r.lone_vertex, 0);
  expect_vec(r.m, Vec3(0.25, 0.25, 0));
  expect_vec(r.n, Vec3(0.35, 0.25, 0));
  expect_vec(r.point, Vec3(0.35, 0.25, 0));
  expect_vec(r.weights_a, Vec3(0.5, 0, 0.5));
  expect_vec(r.force, Vec3(0, 0, -300), 1e-9);

  // The other relabelled case: edge A3A1 inside (A1, A3 below, A2 above) → lone vertex index 1,
  // A1' = A3, A2' = A1. M on A3→A2 = (0.35, 0.25, 0), N on A1→A2 = (0.25, 0.25, 0) = P.
  const ContactTriangles t2 = tissue_with(Vec3(0.2, 0.2, -0.1), Vec3(0.3, 0.3, 0.1), Vec3(0.4, 0.2, -0.1));
  const ContactResponse r2 = respond_contact(t2, straight_box(), nullptr, {}, kSeed);
  ASSERT_EQ(r2.status, ContactStatus::kApplied);
  EXPECT_EQ(r2.lone_vertex, 1);
  expect_vec(r2.m, Vec3(0.35, 0.25, 0));
  expect_vec(r2.point, Vec3(0.25, 0.25, 0));
  expect_vec(r2.weights_b, Vec3(0.5, 0.25, 0.25));
}

TEST(ResponseCases, NOutsideMovedToEdge_Fig3_6a_3_7a) {
  // A1 = (0.3,0.2,0.1), A2 = (1.3,0.2,0.1), A3 = (0.5,0.2,−0.1): M = (0.4,0.2,0) (inside B),
  // N = A2 + 0.5(A3 − A2) = (0.9, 0.2, 0): λ1 = 1 − 0.9 − 0.2 = −0.1 < 0, outside.
  // MN runs along y = 0.2 and leaves B where x + y = 1: x = 0.8, s = (0.8 − 0.4)/(0.9 − 0.4) = 0.8.
  // P = (0.8, 0.2, 0) on edge B2B3, λ = (0, 0.8, 0.2).
  // In A: (1−s)(1−tM) = 0.1, s(1−tN) = 0.4, (1−s)tM + s·tN = 0.5;
  // check: 0.1·A1 + 0.4·A2 + 0.5·A3 = (0.03 + 0.52 + 0.25, 0.2, 0.01 + 0.04 − 0.05) = P.
  const ContactTriangles t = tissue_with(Vec3(0.3, 0.2, 0.1), Vec3(1.3, 0.2, 0.1), Vec3(0.5, 0.2, -0.1));
  const ContactResponse r = respond_contact(t, straight_box(), nullptr, {}, kSeed);
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  EXPECT_TRUE(r.moved_to_edge);
  expect_vec(r.n, Vec3(0.9, 0.2, 0));
  expect_vec(r.point, Vec3(0.8, 0.2, 0));
  expect_vec(r.weights_b, Vec3(0, 0.8, 0.2));
  expect_vec(r.weights_a, Vec3(0.1, 0.4, 0.5));
}

TEST(ResponseCases, BothEndsOutsideMovedToEdge_Fig3_6b_3_7b) {
  // The instrument triangle is wider than B: A1 = (−0.9,0.2,0.1), A2 = (1.3,0.2,0.1),
  // A3 = (0.5,0.2,−0.1): M = (−0.2, 0.2, 0) (λ2 = −0.2 < 0), N = (0.9, 0.2, 0) (λ1 = −0.1 < 0).
  // Inside B for x ∈ [0, 0.8]; P is the end nearer N: (0.8, 0.2, 0), s = 1.0/1.1.
  const ContactTriangles t = tissue_with(Vec3(-0.9, 0.2, 0.1), Vec3(1.3, 0.2, 0.1), Vec3(0.5, 0.2, -0.1));
  const ContactResponse r = respond_contact(t, straight_box(), nullptr, {}, kSeed);
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  EXPECT_TRUE(r.moved_to_edge);
  expect_vec(r.m, Vec3(-0.2, 0.2, 0));
  expect_vec(r.point, Vec3(0.8, 0.2, 0));
  expect_vec(r.weights_b, Vec3(0, 0.8, 0.2));
}

TEST(ResponseCases, PExactlyOnTissueVertex) {
  // MN runs along edge B1B2 (y = 0): A1 = (0.5,0,0.1), A2 = (1.5,0,0.1), A3 = (1,0,−0.1):
  // M = (0.75,0,0), N = (1.25,0,0) outside; λ3 stays exactly 0 along MN; P = B2 = (1,0,0).
  const ContactTriangles t = tissue_with(Vec3(0.5, 0, 0.1), Vec3(1.5, 0, 0.1), Vec3(1, 0, -0.1));
  const ContactResponse r = respond_contact(t, straight_box(), nullptr, {}, kSeed);
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  expect_vec(r.point, Vec3(1, 0, 0));
  expect_vec(r.weights_b, Vec3(0, 1, 0));
}

TEST(ResponseCases, PiercedOrganFarSideDiscarded_Fig3_12) {
  // A slab organ 0.02 m thick: surface 1 is B (z = 0, n_out = +z); surface 2 is
  // B' = (0,0,−0.02), (0,1,−0.02), (1,0,−0.02), wound so that n_out = (0,1,0)×(1,0,0) = −z.
  // A vertical instrument triangle pierces both; its top vertex is at (0.3, 0.3, 0.5).
  // Surface 1: n_out·(top − B1) = 0.5 > 0 → kept. Surface 2: (−z)·(top − B'1) = −0.52 < 0 →
  // the far side of a pierced organ, discarded.
  const Vec3 top(0.3, 0.3, 0.5);
  const Vec3 a1(0.25, 0.3, 0.5), a2(0.35, 0.3, 0.5), a3(0.3, 0.3, -0.1);
  Obb box;
  box.center = Vec3(0.3, 0.3, 0.2);
  box.half_extents = Vec3(0.05, 0.01, 0.3);
  const ContactTriangles near_side = tissue_with(a1, a2, a3);
  ContactTriangles far_side = near_side;
  far_side.b = {Vec3(0, 0, -0.02), Vec3(0, 1, -0.02), Vec3(1, 0, -0.02)};
  const ContactResponse r1 = respond_contact(near_side, box, &top, {}, kSeed);
  const ContactResponse r2 = respond_contact(far_side, box, &top, {}, kSeed);
  EXPECT_EQ(r1.status, ContactStatus::kApplied);
  EXPECT_EQ(r2.status, ContactStatus::kPierced);
  EXPECT_EQ(r2.force, Vec3::Zero());
  // Surface 1 alone: P = N on A2A3 at z = 0: t = 0.5/0.6, P = (0.35 − 0.05·5/6, 0.3, 0);
  // the box's z ray along −z leaves at z = −0.1: PD = (0,0,−0.1), resting f = 200 N.
  expect_vec(r1.point, Vec3(0.35 - 0.05 * 5.0 / 6.0, 0.3, 0), 1e-12);
  expect_vec(r1.force, Vec3(0, 0, -200), 1e-9);
  // Without the filter the far side would push the organ up (+z) by the box's top part:
  // ray along +z from z = −0.02 leaves at z = 0.5: PD = (0,0,0.52), f = 1040 N, wrong way.
  ResponseSettings off = kSeed;
  off.pierce_filter = false;
  const ContactResponse r3 = respond_contact(far_side, box, &top, {}, off);
  ASSERT_EQ(r3.status, ContactStatus::kApplied);
  expect_vec(r3.force, Vec3(0, 0, 1040), 1e-9);
}

// Tilted box for Fig. 3.11: axes a1 = (c,0,−c), a2 = (0,1,0), a3 = a1×a2 = (c,0,c), c = 1/√2;
// centre = P − (0,0,0.05) so P's local coordinates are p = (−0.05c, 0, 0.05c); h = (0.2,0.05,0.1).
// n_in = (0,0,−1): a1·n_in = c > 0 → t1 = h1 − p1 = 0.2 + 0.05c, Pd1 = t1·a1;
// a2·n_in = 0 → nothing; a3·n_in = −c < 0 → t3 = h3 + p3 = 0.1 + 0.05c, Pd3 = −t3·a3.
// PD = (c(t1 − t3), 0, −c(t1 + t3)) = (0.1c, 0, −c(0.3 + 0.1c)) = (0.0707107, 0, −0.2621320).
const Real kC = std::sqrt(0.5);
const Real kT1 = 0.2 + 0.05 * kC;
const Real kT3 = 0.1 + 0.05 * kC;
Obb tilted_box(const Vec3& p) {
  Obb b;
  b.axes.col(0) = Vec3(kC, 0, -kC);
  b.axes.col(1) = Vec3(0, 1, 0);
  b.axes.col(2) = Vec3(kC, 0, kC);
  b.center = p - Vec3(0, 0, 0.05);
  b.half_extents = Vec3(0.2, 0.05, 0.1);
  return b;
}

TEST(ResponseCases, PenetrationVectorMatchesRayObbExits_Eq3_7) {
  const Vec3 p(0.35, 0.25, 0);
  const Obb box = tilted_box(p);
  const Vec3 pd = obb_penetration(box, p, Vec3(0, 0, -1));
  expect_vec(pd, Vec3(0.1 * kC, 0, -kC * (0.3 + 0.1 * kC)));
  // The same from the geometry module's ray–OBB exits.
  const RayObbHit h1 = intersect_ray_obb(box, p, box.axes.col(0));
  const RayObbHit h3 = intersect_ray_obb(box, p, -box.axes.col(2));
  ASSERT_TRUE(h1.origin_inside && h3.origin_inside);
  expect_vec(pd, (h1.exit - p) + (h3.exit - p));
  EXPECT_NEAR(h1.t_exit, kT1, kTol);
  EXPECT_NEAR(h3.t_exit, kT3, kTol);
}

TEST(ResponseCases, SamePenetrationThreeVelocityDirections_Fig3_11) {
  // Fig. 3.5a's triangles (P = (0.35, 0.25, 0)) with the tilted box: the same PD, three motions.
  const Vec3 a1(0.2, 0.2, 0.1), a2(0.4, 0.2, 0.1), a3(0.3, 0.3, -0.1);
  const Vec3 p(0.35, 0.25, 0);
  const Obb box = tilted_box(p);
  const Vec3 pd(0.1 * kC, 0, -kC * (0.3 + 0.1 * kC));
  // (a) instrument straight down (0,0,−1): D = (PD·v̂)v̂ = 0.2621320·(0,0,−1);
  //     f = 2000·0.2621320 + 5·1 = 529.2640 N.
  {
    const ContactResponse r = respond_contact(tissue_with(a1, a2, a3, Vec3(0, 0, -1)), box, nullptr, {}, kSeed);
    ASSERT_EQ(r.status, ContactStatus::kApplied);
    expect_vec(r.penetration, pd);
    expect_vec(r.deformation, Vec3(0, 0, pd.z()));
    EXPECT_NEAR(r.force.z(), -(2000 * -pd.z() + 5), 1e-9);
  }
  // (b) instrument along a1 = (1,0,−1)/√2 at 1 m/s: PD·a1 = t1 (a1 ⟂ a3) = 0.2353553,
  //     D = t1·a1 = (0.1664214, 0, −0.1664214); v·n_in = c; f = 2000·t1 + 5c = 474.2463 N.
  {
    const Vec3 v(kC, 0, -kC);
    const ContactResponse r = respond_contact(tissue_with(a1, a2, a3, v), box, nullptr, {}, kSeed);
    ASSERT_EQ(r.status, ContactStatus::kApplied);
    expect_vec(r.penetration, pd);
    expect_vec(r.deformation, kT1 * v);
    EXPECT_NEAR(r.depth, kT1, kTol);
    EXPECT_NEAR(r.force.z(), -(2000 * kT1 + 5 * kC), 1e-9);
  }
  // (c) instrument (0,0,−1), tissue (1,0,0): v_rel = (−1,0,−1), v̂ = −a3: PD·v̂ = t3 = 0.1353553,
  //     D = t3·(−c,0,−c); v_rel·n_in = 1; f = 2000·t3 + 5 = 275.7107 N.
  {
    const ContactResponse r =
        respond_contact(tissue_with(a1, a2, a3, Vec3(0, 0, -1), Vec3(1, 0, 0)), box, nullptr, {}, kSeed);
    ASSERT_EQ(r.status, ContactStatus::kApplied);
    expect_vec(r.relative_velocity, Vec3(-1, 0, -1));
    expect_vec(r.deformation, kT3 * Vec3(-kC, 0, -kC));
    EXPECT_NEAR(r.force.z(), -(2000 * kT3 + 5), 1e-9);
  }
  // Receding (0,0,+1): PD·v̂ < 0 → fallback D = (PD·n_in) n_in; damping −5: f = 524.2640 − 5.
  {
    const ContactResponse r = respond_contact(tissue_with(a1, a2, a3, Vec3(0, 0, 1)), box, nullptr, {}, kSeed);
    expect_vec(r.deformation, Vec3(0, 0, pd.z()));
    EXPECT_NEAR(r.force.z(), -(2000 * -pd.z() - 5), 1e-9);
  }
}

TEST(ResponseCases, RestingContact) {
  // Nothing moves: v_rel = 0 < resting_speed → D = (PD·n_in) n_in = (0,0,−0.2621320),
  // f = 2000·0.2621320 = 524.2641 N, no damping term.
  const Vec3 p(0.35, 0.25, 0);
  const ContactResponse r = respond_contact(
      tissue_with(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1)), tilted_box(p), nullptr, {}, kSeed);
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  const Real depth = kC * (0.3 + 0.1 * kC);
  expect_vec(r.deformation, Vec3(0, 0, -depth));
  EXPECT_NEAR(r.force.z(), -2000 * depth, 1e-9);
  // Slower than the threshold counts as resting too.
  const ContactResponse r2 = respond_contact(
      tissue_with(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1), Vec3(1e-8, 0, 0)), tilted_box(p),
      nullptr, {}, kSeed);
  expect_vec(r2.deformation, Vec3(0, 0, -depth));
}

TEST(ResponseCases, Baselines) {
  // Fig. 3.5a triangles, straight box, at rest.
  const ContactTriangles t = tissue_with(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1));
  ResponseSettings s;
  // primitive: deepest vertex of A below the plane: A3 at 0.1 → D = (0,0,−0.1), f = 200 N.
  s.method = ResponseMethod::kPrimitive;
  ContactResponse r = respond_contact(t, straight_box(), nullptr, {}, s);
  expect_vec(r.deformation, Vec3(0, 0, -0.1));
  expect_vec(r.force, Vec3(0, 0, -200), 1e-9);
  // normal: deepest instrument vertex; with an extra vertex at z = −0.3: D = (0,0,−0.3), 600 N.
  s.method = ResponseMethod::kNormal;
  const Vec3 instrument[] = {t.a[0], t.a[1], t.a[2], Vec3(0.3, 0.3, -0.3)};
  r = respond_contact(t, straight_box(), nullptr, instrument, s);
  expect_vec(r.force, Vec3(0, 0, -600), 1e-9);
  // project: the seed's D (0.15 deep, straight box) → 300 N; with the depth cap, A3's 0.1 → 200 N.
  s.method = ResponseMethod::kProject;
  s.depth_cap = false;
  r = respond_contact(t, straight_box(), nullptr, {}, s);
  expect_vec(r.force, Vec3(0, 0, -300), 1e-9);
  s.depth_cap = true;
  r = respond_contact(t, straight_box(), nullptr, {}, s);
  expect_vec(r.force, Vec3(0, 0, -200), 1e-9);
  EXPECT_EQ(parse_response_method("normal"), ResponseMethod::kNormal);
  EXPECT_EQ(parse_response_method("OBB"), std::nullopt);
  EXPECT_STREQ(response_method_name(ResponseMethod::kPrimitive), "primitive");
}

TEST(ResponseCases, DegenerateInputsGiveNoNaN) {
  const Obb box = straight_box();
  // Coplanar: the instrument triangle lies in the tissue plane → no force.
  ContactResponse r = respond_contact(tissue_with(Vec3(0.1, 0.1, 0), Vec3(0.5, 0.1, 0), Vec3(0.1, 0.5, 0)), box,
                                      nullptr, {}, {});
  EXPECT_EQ(r.status, ContactStatus::kCoplanar);
  // Zero-area tissue triangle → no normal, no force.
  ContactTriangles t = tissue_with(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1));
  t.b = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  EXPECT_EQ(respond_contact(t, box, nullptr, {}, {}).status, ContactStatus::kDegenerateTissue);
  t.b = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0)};
  EXPECT_EQ(respond_contact(t, box, nullptr, {}, {}).status, ContactStatus::kDegenerateTissue);
  // Zero-area instrument triangle (a segment through the plane): works as the segment.
  r = respond_contact(tissue_with(Vec3(0.3, 0.3, 0.1), Vec3(0.3, 0.3, 0.1), Vec3(0.3, 0.3, -0.1)), box, nullptr, {}, {});
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  expect_vec(r.point, Vec3(0.3, 0.3, 0));
  EXPECT_TRUE(r.force.allFinite());
  // An instrument vertex exactly on the plane counts as outside: A1 on it, A3 below → M = A1.
  r = respond_contact(tissue_with(Vec3(0.2, 0.2, 0), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1)), box, nullptr, {}, {});
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  expect_vec(r.m, Vec3(0.2, 0.2, 0));
  // The lone vertex on the plane with two below: M = N = A3, P = A3.
  r = respond_contact(tissue_with(Vec3(0.2, 0.2, -0.1), Vec3(0.4, 0.2, -0.1), Vec3(0.3, 0.3, 0)), box, nullptr, {}, {});
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  expect_vec(r.point, Vec3(0.3, 0.3, 0));
  // Touching from above only (no vertex inside) → no crossing, no force.
  r = respond_contact(tissue_with(Vec3(0.2, 0.2, 0), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, 0.1)), box, nullptr, {}, {});
  EXPECT_EQ(r.status, ContactStatus::kNoCrossing);
  // Zero relative velocity → resting (above); MN missing B → kMissed.
  r = respond_contact(tissue_with(Vec3(2.2, 0.2, 0.1), Vec3(2.4, 0.2, 0.1), Vec3(2.3, 0.3, -0.1)), box, nullptr, {}, {});
  EXPECT_EQ(r.status, ContactStatus::kMissed);
  EXPECT_TRUE(r.force.allFinite());
  EXPECT_STREQ(contact_status_name(ContactStatus::kPierced), "pierced");
}

}  // namespace
}  // namespace trocar
