// Contact inside the XPBD solver (response/solver_contact.h), case by case with the numbers
// worked out by hand: a vertex against a plane and a sphere, a wire under a coarse triangle,
// friction sticking and slipping, and the jaws holding a vertex as an attachment.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "trocar/geometry/signed_distance.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"
#include "trocar/response/solver_contact.h"

namespace trocar {
namespace {

XpbdParticle particle(const Vec3& p, Real inverse_mass) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
          static_cast<float>(inverse_mass)};
}
Vec3 at(const XpbdParticle& p) { return Vec3(p.x, p.y, p.z); }

/// One instrument and a few loose tissue particles of 1 g (and triangles if given), driven
/// through the handler as the solver drives it.
struct Rig {
  Instrument tool;
  InstrumentField field;
  Real thickness = 0.002;
  std::vector<XpbdParticle> x, previous;
  std::vector<Real> masses;
  std::vector<Triangle> triangles;
  ResponseSettings settings;
  InstrumentContacts contacts;

  Rig(TriMesh mesh, std::vector<Vec3> points, Real sample_spacing = 0.001)
      : tool(std::move(mesh)), field(tool.local_mesh(), 0.004, 1u << 16, sample_spacing) {
    for (const Vec3& p : points) x.push_back(particle(p, 1e3));
    previous = x;
    masses.assign(x.size(), 1e-3);
  }
  void reset() {
    std::vector<Vec3> rest;
    for (const XpbdParticle& p : x) rest.push_back(at(p));
    const SolverInstrument in{&tool, &field, thickness};
    contacts.reset(rest, triangles, true, std::span(&in, 1), settings);
  }
  /// One step of `substeps` with positions x already predicted (previous = the step's start).
  void step(Real dt = 1e-3, int substeps = 1) {
    const XpbdView view{x, previous, masses, triangles};
    contacts.begin_step(view, substeps);
    for (int s = 0; s < substeps; ++s) contacts.solve(view, s, substeps, dt / substeps);
  }
};

// A 10 × 10 × 2 cm box: its top face z = 1 cm is a plane. A vertex predicted 2 mm under it, from
// outside, goes back to z = 1 cm + margin, straight up (no tangential slip); the instrument feels
// −m Δx / h² (1 g × 2.05 mm / 1 ms² = 2.05 N down).
TEST(SolverContact, VertexAgainstAPlane) {
  Rig rig(make_box(0.1, 0.1, 0.02), {Vec3(0.001, 0.002, 0.008)});
  rig.previous[0] = particle(Vec3(0.001, 0.002, 0.011), 1e3);
  rig.reset();
  rig.step();
  const Real margin = rig.settings.contact_margin;
  EXPECT_NEAR(rig.x[0].x, 0.001, 1e-9);
  EXPECT_NEAR(rig.x[0].y, 0.002, 1e-9);
  EXPECT_NEAR(rig.x[0].z, 0.01 + margin, 1e-8);
  EXPECT_NEAR(rig.contacts.force(0).z(), -1e-3 * (0.002 + margin) / 1e-6, 1e-4);
  EXPECT_NEAR(rig.contacts.force(0).x(), 0, 1e-6);
  EXPECT_EQ(rig.contacts.contacts(), 1u);
}

// A vertex 1 mm inside a sphere (icosphere, r = 1 cm) ends on the outward normal through its
// nearest surface point, `margin` outside; MeshDistance, queried independently, agrees.
TEST(SolverContact, VertexAgainstASphere) {
  const TriMesh ball = make_icosphere(0.01, 3);
  const Vec3 inside = Vec3(0.3, -0.5, 0.8).normalized() * 0.009;
  Rig rig(ball, {inside});
  rig.reset();
  rig.step();
  const MeshDistance exact(ball.positions, ball.triangles);
  const SignedDistanceResult r = exact.signed_distance(inside);
  ASSERT_LT(r.distance, 0);
  const Vec3 expected = r.closest_point + rig.settings.contact_margin * (r.closest_point - inside).normalized();
  EXPECT_NEAR((at(rig.x[0]) - expected).norm(), 0, 2e-8);
  EXPECT_NEAR(exact.signed_distance(at(rig.x[0])).distance, rig.settings.contact_margin, 2e-8);
}

/// A horizontal triangle with 2 cm edges (outward normal +z) and a 1.2 mm wire along x whose
/// axis is 0.2 mm above it, so its underside is 0.4 mm into the tissue, between the vertices.
Rig wire_rig(Real sample_spacing) {
  TriMesh wire = make_cylinder(0.0006, 0.04, 12);  // along z, z ∈ [0, 4 cm]
  Rig rig(std::move(wire), {Vec3(-0.01, -0.01, 0), Vec3(0.01, -0.01, 0), Vec3(0, 0.01, 0)}, sample_spacing);
  rig.triangles = {Triangle{0, 1, 2}};
  rig.thickness = 0.0012;
  Pose pose;
  pose.rotation = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));  // z → x
  pose.translation = Vec3(-0.02, 0, 0.0002);  // x ∈ [−2, 2] cm
  rig.tool.reset_pose(pose);
  rig.reset();
  return rig;
}

/// Height of the triangle's plane at (x, y).
Real face_height(const Rig& rig, Real px, Real py) {
  const Vec3 a = at(rig.x[0]), b = at(rig.x[1]), c = at(rig.x[2]);
  const Vec3 n = (b - a).cross(c - a);
  return a.z() - (n.x() * (px - a.x()) + n.y() * (py - a.y())) / n.z();
}

// The wire's vertices are at its ends, outside the triangle: with vertices alone nothing pushes
// the face and the wire stays 0.4 mm inside it. With samples every 1 mm along its edges, every
// sample over the face ends at least `margin` above it: the face moved down under the wire.
TEST(SolverContact, WireUnderACoarseTriangle) {
  Rig bare = wire_rig(0);
  bare.step();
  EXPECT_NEAR(face_height(bare, 0, 0), 0, 1e-12);

  Rig rig = wire_rig(0.001);
  rig.step();
  const Real margin = rig.settings.contact_margin;
  int over = 0;
  for (const Vec3& local : rig.field.samples()) {
    const Vec3 a = rig.tool.pose().apply(local);
    if (std::abs(a.x()) > 0.004 || std::abs(a.y()) > 0.001) continue;  // well inside the face
    ++over;
    EXPECT_LE(face_height(rig, a.x(), a.y()), a.z() - margin + 1e-7) << a.transpose();
  }
  EXPECT_GT(over, 10);
  EXPECT_LT(face_height(rig, 0, 0), -0.0004 - margin + 1e-7);
  // The face only moved down (every push is along −n).
  for (const XpbdParticle& p : rig.x) EXPECT_LE(p.z, 0.f);
  EXPECT_GT(rig.contacts.force(0).z(), 0) << "the wire pushes the face down, the face the wire up";
  EXPECT_LT(rig.contacts.force(0).z(), 1e3);
}

/// A vertex resting on the box's top (at the margin) is pressed 0.5 mm in while the box moves
/// `slide` along x in one substep.
Rig friction_rig(Real slide) {
  Rig rig(make_box(0.1, 0.1, 0.02), {Vec3(0.003, 0, 0.0095)});
  rig.previous[0] = particle(Vec3(0.003, 0, 0.01 + rig.settings.contact_margin), 1e3);
  rig.tool.reset_pose(Pose{});
  Pose moved;
  moved.translation = Vec3(slide, 0, 0);
  rig.tool.move_to(moved, 1e-3);
  rig.reset();
  rig.step();
  return rig;
}

// Normal correction |Δn| = 0.5 mm + margin = 0.55 mm; μs = μk = 0.6, so the limit is 0.33 mm.
// A 0.2 mm slide is under it: the vertex sticks and moves with the box (x + 0.2 mm). A 1 mm
// slide is over it: the vertex slips, dragged by μk·|Δn| = 0.33 mm only.
TEST(SolverContact, FrictionSticksThenSlips) {
  const ResponseSettings s;
  const Real normal = 0.0005 + s.contact_margin;
  const Rig stick = friction_rig(0.0002);
  EXPECT_NEAR(stick.x[0].x, 0.003 + 0.0002, 1e-8);
  EXPECT_NEAR(stick.x[0].z, 0.01 + s.contact_margin, 1e-8);
  const Rig slip = friction_rig(0.001);
  EXPECT_NEAR(slip.x[0].x, 0.003 + s.friction_kinetic * normal, 1e-8);
  EXPECT_NEAR(slip.x[0].z, 0.01 + s.contact_margin, 1e-8);
  // The tangential force on the box opposes its motion.
  EXPECT_LT(stick.contacts.force(0).x(), 0);
  EXPECT_LT(slip.contacts.force(0).x(), 0);
}

// Closed jaws hold a vertex within 1 mm of a jaw triangle: it follows the instrument's pose
// exactly (an attachment solved after the tissue's constraints); an open jaw lets it go.
TEST(SolverContact, ClosedJawsHoldAVertexAsAnAttachment) {
  const InstrumentMesh grasper = make_grasper();
  ASSERT_FALSE(grasper.jaw_triangles.empty());
  const Triangle& jt = grasper.mesh.triangles[grasper.jaw_triangles[0]];
  const Vec3 a = grasper.mesh.positions[jt[0]], b = grasper.mesh.positions[jt[1]], c = grasper.mesh.positions[jt[2]];
  const Vec3 near = (a + b + c) / 3 + 0.0003 * (b - a).cross(c - a).normalized();
  Rig rig(grasper.mesh, {near, Vec3(0.5, 0.5, 0.5)});
  rig.tool.set_jaw_triangles(grasper.jaw_triangles);
  rig.tool.set_jaw(1);
  rig.reset();
  rig.step();
  ASSERT_EQ(rig.contacts.held(0).size(), 1u);
  EXPECT_EQ(rig.contacts.held(0)[0].vertex, 0u);
  // The grasper moves 1 cm and turns 10°: the vertex goes with it.
  Pose moved;
  moved.translation = Vec3(0.01, 0, 0);
  moved.rotation = Quat(Eigen::AngleAxisd(10 * M_PI / 180, Vec3::UnitX()));
  rig.tool.move_to(moved, 1e-3);
  rig.previous = rig.x;
  rig.step(1e-3, 4);
  EXPECT_NEAR((at(rig.x[0]) - moved.apply(near)).norm(), 0, 1e-8);
  EXPECT_EQ(rig.x[1].x, 0.5f);  // far away: untouched
  // Held 1 mm off its place (the tissue pulled it): the attachment puts it back and the jaws
  // feel m Δx / h² = 1 g × 1 mm / 1 ms² = 1 N toward the pull.
  rig.tool.move_to(moved, 1e-3);  // at rest now
  rig.previous = rig.x;
  rig.x[0].z -= 0.001f;
  rig.step();
  EXPECT_NEAR((at(rig.x[0]) - moved.apply(near)).norm(), 0, 1e-8);
  EXPECT_NEAR(rig.contacts.force(0).z(), -1.0, 1e-3);
  rig.tool.set_jaw(0);
  rig.step();
  EXPECT_TRUE(rig.contacts.held(0).empty());
}

TEST(SolverContact, PoseInterpolationEndsAtBothPoses) {
  Pose a, b;
  a.translation = Vec3(1, 2, 3);
  b.translation = Vec3(2, 2, 3);
  b.rotation = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ()));
  EXPECT_NEAR((interpolate_pose(a, b, 0).translation - a.translation).norm(), 0, 1e-15);
  EXPECT_NEAR((interpolate_pose(a, b, 1).translation - b.translation).norm(), 0, 1e-15);
  EXPECT_NEAR(interpolate_pose(a, b, 0.5).rotation.angularDistance(Quat(Eigen::AngleAxisd(0.25, Vec3::UnitZ()))), 0,
              1e-12);
}

// The port (Instrument::set_port): a 5 mm shaft along z, z ∈ [0, 20 cm], its tip at the origin;
// a vertex 1 mm inside it 15 cm up the shaft, under the middle of a side of the 16-gon. With the
// port at 10 cm it lies outside the body and stays where it is, with no force on the shaft; with
// the port at 18 cm it is inside and goes out to that side + margin, radially.
TEST(SolverContact, NothingIsTouchedBeyondThePort) {
  const Vec3 radial(std::cos(M_PI / 16), std::sin(M_PI / 16), 0);
  const Vec3 inside = 0.0015 * radial + Vec3(0, 0, 0.15);
  for (const Real port : {0.10, 0.18}) {
    Rig rig(make_cylinder(0.0025, 0.2, 16, true), {inside});
    rig.tool.set_port(Vec3(0.01, 0.01, port));  // off the axis: only its height along the shaft counts
    rig.reset();
    const Vec3 start = at(rig.x[0]);  // inside, in the particle's float
    rig.step();
    const Vec3 x = at(rig.x[0]);
    if (port < 0.15) {
      EXPECT_EQ((x - start).norm(), 0) << "port at " << port;
      EXPECT_EQ(rig.contacts.force(0).norm(), 0);
      EXPECT_EQ(rig.contacts.contacts(), 0u);
    } else {
      // The side's distance from the axis (the 16-gon's apothem) is 2.5 cos(π/16) mm.
      EXPECT_NEAR(x.dot(radial), 0.0025 * std::cos(M_PI / 16) + rig.settings.contact_margin, 1e-6);
      EXPECT_NEAR((x - x.dot(radial) * radial - Vec3(0, 0, 0.15)).norm(), 0, 1e-6);
      EXPECT_LT(rig.contacts.force(0).dot(radial), 0);  // the vertex pushed out pushes the shaft back
      EXPECT_EQ(rig.contacts.contacts(), 1u);
    }
  }
}

// And a face under the shaft: the wire of WireUnderACoarseTriangle (0.4 mm into the face, its
// tip end at x = −2 cm) pushes the face down only while its samples over it are inside the body.
// With the port at x = −3 cm, the whole wire lies beyond it and the face is left alone.
TEST(SolverContact, NoFaceIsPushedBeyondThePort) {
  Rig inside = wire_rig(0.001);
  inside.tool.set_port(Vec3(0.03, 0, 0));
  inside.step();
  EXPECT_LT(face_height(inside, 0, 0), -0.0003);
  Rig outside = wire_rig(0.001);
  outside.tool.set_port(Vec3(-0.03, 0, 0));
  outside.step();
  EXPECT_EQ(face_height(outside, 0, 0), 0);
}

}  // namespace
}  // namespace trocar
