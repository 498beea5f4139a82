// Instrument: OBB carried by the pose, velocities from two poses, top vertex, jaws.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "trocar/instrument/instrument.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<Real> g;
  Quat q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q;
}

TEST(Instrument, ObbContainsEveryVertexInEveryPose) {
  // A capsule shaft (r = 2.5 mm, 0.3 m long) tilted and moved to 200 random poses: the box
  // fitted once and carried by the pose holds every world vertex (tolerance 1e-12 m: rounding).
  Instrument tool(make_capsule(0.0025, 0.3, 12, 4));
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(-0.5, 0.5);
  for (int i = 0; i < 200; ++i) {
    Pose p;
    p.rotation = random_rotation(rng);
    p.translation = Vec3(u(rng), u(rng), u(rng));
    tool.move_to(p, 1e-3);
    for (const Vec3& x : tool.world_positions()) ASSERT_TRUE(tool.world_obb().contains(x, 1e-12));
    // The box is the local one carried by the pose, not refitted: same extents.
    EXPECT_EQ(tool.world_obb().half_extents, tool.local_obb().half_extents);
    EXPECT_LT((tool.world_obb().center - p.apply(tool.local_obb().center)).norm(), 1e-14);
  }
}

TEST(Instrument, WorldPositionsFollowPose) {
  Instrument tool(make_box(0.01, 0.02, 0.03));
  const Pose p = Pose::from_euler_deg(Vec3(0.1, -0.2, 0.3), Vec3(10, 20, 30));
  tool.reset_pose(p);
  for (std::size_t i = 0; i < tool.world_positions().size(); ++i)
    EXPECT_LT((tool.world_positions()[i] - p.apply(tool.local_mesh().positions[i])).norm(), 1e-15);
  EXPECT_EQ(tool.linear_velocity(), Vec3::Zero());
}

TEST(Instrument, VelocityFromTwoPosesTranslation) {
  // t: (0,0,0.08) → (0,0,0.079) in 1 ms: v = −0.001 m / 0.001 s = (0, 0, −1) m/s; ω = 0.
  Instrument tool(make_box(0.01, 0.01, 0.1));
  tool.reset_pose(Pose::from_euler_deg(Vec3(0, 0, 0.08), Vec3::Zero()));
  tool.move_to(Pose::from_euler_deg(Vec3(0, 0, 0.079), Vec3::Zero()), 1e-3);
  EXPECT_NEAR(tool.linear_velocity().z(), -1.0, 1e-12);
  EXPECT_NEAR(tool.linear_velocity().head<2>().norm(), 0.0, 1e-15);
  EXPECT_NEAR(tool.angular_velocity().norm(), 0.0, 1e-15);
  EXPECT_EQ(tool.previous_pose().translation, Vec3(0, 0, 0.08));
}

TEST(Instrument, VelocityFromTwoPosesRotation) {
  // Rotation about z by 0.9° in 10 ms: ω = (0.9·π/180) / 0.01 = 1.5708 rad/s about +z.
  // At the origin v = 0; at x = (0.1, 0, 0): v = ω × x = (0, 0.15708, 0) m/s.
  Instrument tool(make_box(0.01, 0.01, 0.1));
  tool.reset_pose(Pose::identity());
  tool.move_to(Pose::from_euler_deg(Vec3::Zero(), Vec3(0, 0, 0.9)), 0.01);
  const Real w = 0.9 * std::numbers::pi / 180 / 0.01;
  EXPECT_NEAR(tool.angular_velocity().z(), w, 1e-12);
  EXPECT_NEAR(tool.angular_velocity().head<2>().norm(), 0.0, 1e-14);
  const Vec3 v = tool.velocity_at(Vec3(0.1, 0, 0));
  EXPECT_NEAR(v.y(), 0.1 * w, 1e-12);
  EXPECT_NEAR(v.x(), 0.0, 1e-14);
  // Large rotation (170° about x) and the shortest-way sign (q and −q are the same rotation).
  const Quat q1(Eigen::AngleAxis<Real>(170.0 * std::numbers::pi / 180, Vec3::UnitX()));
  const Vec3 w1 = angular_velocity_between(Quat::Identity(), Quat(-q1.coeffs()), 1.0);
  EXPECT_NEAR(w1.x(), 170.0 * std::numbers::pi / 180, 1e-12);
  EXPECT_EQ(angular_velocity_between(Quat::Identity(), q1, 0.0), Vec3::Zero());
}

TEST(Instrument, TopVertexAutoOnCapsule) {
  // make_capsule(r, L): z ∈ [−r, L + r], origin at the tip-side hemisphere's centre. The tip is
  // the end of the long axis nearer the origin, so the top is the far pole (0, 0, L + r).
  const Real r = 0.0025, len = 0.3;
  Instrument tool(make_capsule(r, len, 12, 4));
  const Vec3 top = tool.local_mesh().positions[tool.top_vertex()];
  EXPECT_NEAR(top.z(), len + r, 1e-12);
  EXPECT_NEAR(top.head<2>().norm(), 0.0, 1e-12);
  // The same shaft flipped (tip at the origin on the −z side): top = (0, 0, −L − r).
  TriMesh flipped = make_capsule(r, len, 12, 4);
  for (Vec3& x : flipped.positions) x.z() = -x.z();
  for (Triangle& t : flipped.triangles) std::swap(t[1], t[2]);
  Instrument tool2(flipped);
  EXPECT_NEAR(tool2.local_mesh().positions[tool2.top_vertex()].z(), -len - r, 1e-12);
  // A given shaft direction wins over the rule: −z picks the pole at z = −r.
  Instrument tool3(make_capsule(r, len, 12, 4), Vec3(0, 0, -1));
  EXPECT_NEAR(tool3.local_mesh().positions[tool3.top_vertex()].z(), -r, 1e-12);
}

TEST(Instrument, TopVertexAutoOnCylinder) {
  // Capped cylinder z ∈ [0, L]: the far cap (z = L) is a tie of 13 vertices; the cap's centre
  // vertex (0, 0, L), nearest the axis, is chosen.
  Instrument tool(make_cylinder(0.005, 0.25, 12, true));
  const Vec3 top = tool.local_mesh().positions[tool.top_vertex()];
  EXPECT_NEAR(top.z(), 0.25, 1e-12);
  EXPECT_NEAR(top.head<2>().norm(), 0.0, 1e-12);
  // World position follows the pose.
  const Pose p = Pose::from_euler_deg(Vec3(0.01, 0.02, 0.03), Vec3(90, 0, 0));
  tool.reset_pose(p);
  EXPECT_LT((tool.top_world() - p.apply(top)).norm(), 1e-15);
  // Uncapped: one of the ring vertices at z = L.
  Instrument tube(make_cylinder(0.005, 0.25, 12, false));
  EXPECT_NEAR(tube.local_mesh().positions[tube.top_vertex()].z(), 0.25, 1e-12);
}

TEST(Instrument, Jaws) {
  Instrument tool(make_box(0.01, 0.01, 0.1));
  EXPECT_FALSE(tool.has_jaws());
  const std::uint32_t jaw[] = {0, 1, 99};  // 99 is out of range: ignored
  tool.set_jaw_triangles(jaw);
  EXPECT_TRUE(tool.has_jaws());
  EXPECT_TRUE(tool.is_jaw_triangle(1));
  EXPECT_FALSE(tool.is_jaw_triangle(2));
  EXPECT_FALSE(tool.is_jaw_triangle(99));
  tool.set_jaw(1.5);
  EXPECT_EQ(tool.jaw(), 1.0);
  tool.set_jaw(std::nan(""));
  EXPECT_EQ(tool.jaw(), 0.0);
}

// The port: a shaft along local +z turned to lie along world +x (90° about y) with its tip at
// x = 1 cm, through a port at x = 6 cm. Beyond the port (x > 6 cm, toward the handle) is outside
// the body, whatever the point's distance from the axis; the port lies 5 cm up the shaft.
TEST(Instrument, ThePortSplitsInsideFromOutside) {
  Instrument tool(make_cylinder(0.0025, 0.2, 12, true));
  EXPECT_NEAR((tool.local_shaft() - Vec3::UnitZ()).norm(), 0, 1e-12);  // auto: tip at the origin
  const Pose pose = Pose::from_euler_deg(Vec3(0.01, 0.002, 0.003), Vec3(0, 90, 0));
  tool.reset_pose(pose);
  EXPECT_FALSE(tool.has_port());
  EXPECT_FALSE(tool.outside_body(Vec3(0.15, 0, 0)));  // no port: nothing is outside
  EXPECT_TRUE(std::isinf(tool.port_height(pose)));
  tool.set_port(Vec3(0.06, 0.002, 0.003));
  ASSERT_TRUE(tool.has_port());
  EXPECT_NEAR(tool.port_height(pose), 0.05, 1e-12);
  EXPECT_TRUE(tool.outside_body(Vec3(0.0601, 0.03, -0.02)));
  EXPECT_FALSE(tool.outside_body(Vec3(0.0599, 0.03, -0.02)));
  EXPECT_FALSE(tool.outside_body(Vec3(0.0, 0.002, 0.003)));  // past the tip: inside
  // Drawn back 2 cm, the port lies 3 cm up the shaft.
  tool.move_to(Pose::from_euler_deg(Vec3(0.03, 0.002, 0.003), Vec3(0, 90, 0)), 1e-3);
  EXPECT_NEAR(tool.port_height(tool.pose()), 0.03, 1e-12);
  tool.set_port(Vec3(std::nan(""), 0, 0));  // ignored
  EXPECT_NEAR(tool.port().x(), 0.06, 1e-15);
}

}  // namespace
}  // namespace trocar
