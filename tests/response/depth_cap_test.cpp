// The depth cap of obb and project (docs/response.md "Depth cap"): |D| is cut to the instrument
// triangle's deepest vertex below the tissue plane, keeping D's direction. Expected values by hand.
//
// Tissue triangle B1 = (0,0,0), B2 = (1,0,0), B3 = (0,1,0): n_in = (0,0,−1). Instrument box:
// axis-aligned, centre (0.3, 0.25, 0), half-extents (0.2, 0.1, 0.15), so x ∈ [0.1, 0.5] and
// z ∈ [−0.15, 0.15]. From any P in the plane z = 0 inside it, only the z ray goes into the
// tissue (the x and y rays run parallel to the plane): PD = (0, 0, −0.15). K = 2000, μ = 5.
#include <gtest/gtest.h>

#include <cmath>

#include "trocar/response/contact_response.h"

namespace trocar {
namespace {

constexpr Real kTol = 1e-12;

ContactTriangles pair(const Vec3& a1, const Vec3& a2, const Vec3& a3, const Vec3& v_instrument = Vec3::Zero()) {
  ContactTriangles t;
  t.a = {a1, a2, a3};
  t.va = {v_instrument, v_instrument, v_instrument};
  t.b = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  t.vb = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  return t;
}

Obb box() {
  Obb b;
  b.center = Vec3(0.3, 0.25, 0);
  b.half_extents = Vec3(0.2, 0.1, 0.15);
  return b;
}

ResponseSettings with_cap(bool cap, ResponseMethod method = ResponseMethod::kObb) {
  ResponseSettings s;
  s.method = method;
  s.depth_cap = cap;
  return s;
}

void expect_vec(const Vec3& got, const Vec3& want) {
  EXPECT_LT((got - want).norm(), kTol) << "got " << got.transpose() << " want " << want.transpose();
}

TEST(DepthCap, RestingContactIsCutToTheTrianglesDepth) {
  // Fig. 3.5a's triangle: A3 = (0.3, 0.3, −0.1) is 0.1 below the plane. Seed: |D| = PD·n_in =
  // 0.15, f = 300 N. Capped: |D| = 0.1, D = (0, 0, −0.1), f = 200 N.
  const ContactTriangles t = pair(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1));
  const ContactResponse seed = respond_contact(t, box(), nullptr, {}, with_cap(false));
  ASSERT_EQ(seed.status, ContactStatus::kApplied);
  EXPECT_NEAR(seed.depth, 0.15, kTol);
  EXPECT_FALSE(seed.depth_capped);
  const ContactResponse r = respond_contact(t, box(), nullptr, {}, with_cap(true));
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  expect_vec(r.penetration, Vec3(0, 0, -0.15));  // PD itself is the seed's
  EXPECT_NEAR(r.depth, 0.1, kTol);
  EXPECT_TRUE(r.depth_capped);
  expect_vec(r.deformation, Vec3(0, 0, -0.1));
  expect_vec(r.force, Vec3(0, 0, -200));
}

TEST(DepthCap, MovingContactKeepsTheDirectionOfRelativeMotion) {
  // Instrument moving along v̂ = (1, 0, −1)/√2 at 1 m/s: seed |D| = PD·v̂ = 0.15/√2 = 0.1060660,
  // capped to 0.1 along v̂: D = 0.1·v̂; f = 2000·0.1 + 5·(v·n_in) = 200 + 5/√2 = 203.5355339 N.
  const Real c = 1 / std::sqrt(Real{2});
  const Vec3 v(c, 0, -c);
  const ContactTriangles t = pair(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1), v);
  const ContactResponse seed = respond_contact(t, box(), nullptr, {}, with_cap(false));
  EXPECT_NEAR(seed.depth, 0.15 * c, kTol);
  const ContactResponse r = respond_contact(t, box(), nullptr, {}, with_cap(true));
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  EXPECT_NEAR(r.depth, 0.1, kTol);
  expect_vec(r.deformation, 0.1 * v);
  EXPECT_NEAR(r.force.z(), -(200 + 5 * c), 1e-9);
  // The same for `project`, whose D is also the position correction.
  const ContactResponse p = respond_contact(t, box(), nullptr, {}, with_cap(true, ResponseMethod::kProject));
  expect_vec(p.deformation, 0.1 * v);
}

TEST(DepthCap, BoxShapedInstrumentPressingFaceFirstIsUnchanged) {
  // The instrument triangle lies on the box's face x = 0.1 and reaches its bottom: A3 =
  // (0.1, 0.25, −0.15) is 0.15 below the plane, as deep as PD·n_in. P = N = (0.1, 0.275, 0).
  const ContactTriangles t = pair(Vec3(0.1, 0.2, 0.15), Vec3(0.1, 0.3, 0.15), Vec3(0.1, 0.25, -0.15));
  const ContactResponse seed = respond_contact(t, box(), nullptr, {}, with_cap(false));
  const ContactResponse r = respond_contact(t, box(), nullptr, {}, with_cap(true));
  ASSERT_EQ(r.status, ContactStatus::kApplied);
  expect_vec(r.point, Vec3(0.1, 0.275, 0));
  EXPECT_NEAR(seed.depth, 0.15, kTol);
  EXPECT_NEAR(r.depth, 0.15, kTol);
  EXPECT_FALSE(r.depth_capped);
  expect_vec(r.force, seed.force);
}

TEST(DepthCap, ForceVanishesAsTheContactOpens) {
  // A3 at depth ε below the plane: the seed's force stays 2000·0.15 = 300 N however small ε is
  // (a step from 0 at first touch: the chatter of docs/response.md); capped it is 2000·ε.
  for (const Real eps : {1e-2, 1e-4, 1e-6}) {
    const ContactTriangles t = pair(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -eps));
    const ContactResponse seed = respond_contact(t, box(), nullptr, {}, with_cap(false));
    const ContactResponse r = respond_contact(t, box(), nullptr, {}, with_cap(true));
    ASSERT_EQ(r.status, ContactStatus::kApplied) << eps;
    EXPECT_NEAR(seed.force.norm(), 300, 1e-9) << eps;
    EXPECT_NEAR(r.depth, eps, 1e-15) << eps;
    EXPECT_NEAR(r.force.norm(), 2000 * eps, 1e-9) << eps;
  }
}

TEST(DepthCap, BaselinesIgnoreIt) {
  // primitive and normal have no box depth to cap: the same result either way.
  const ContactTriangles t = pair(Vec3(0.2, 0.2, 0.1), Vec3(0.4, 0.2, 0.1), Vec3(0.3, 0.3, -0.1));
  for (const ResponseMethod m : {ResponseMethod::kPrimitive, ResponseMethod::kNormal}) {
    const ContactResponse a = respond_contact(t, box(), nullptr, {}, with_cap(false, m));
    const ContactResponse b = respond_contact(t, box(), nullptr, {}, with_cap(true, m));
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_FALSE(b.depth_capped);
    EXPECT_NEAR(b.depth, 0.1, kTol);
  }
}

}  // namespace
}  // namespace trocar
