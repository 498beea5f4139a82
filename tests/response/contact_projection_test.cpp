// The sdf response: InstrumentField's bound and ContactProjector's constraint, with numbers
// worked out by hand on a box instrument (docs/response.md "Contact as a constraint").
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "trocar/geometry/barycentric.h"
#include "trocar/geometry/signed_distance.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"
#include "trocar/response/contact_projection.h"
#include "trocar/response/instrument_field.h"

namespace trocar {
namespace {

// The field's grid value is a lower bound of the exact distance everywhere, and tight to within
// h√3 near the surface (so the cull sends only near points to the exact query).
TEST(InstrumentField, GridIsALowerBoundOfTheExactDistance) {
  const TriMesh hook = make_hook_probe().mesh;
  const InstrumentField field(hook, 0.004, 1u << 14);
  const MeshDistance exact(hook.positions, hook.triangles);
  ASSERT_GT(field.cell_size(), 0);
  std::mt19937_64 rng(7);
  const Aabb box = field.box().inflated(0.01);
  std::uniform_real_distribution<double> ux(box.min.x(), box.max.x()), uy(box.min.y(), box.max.y()),
      uz(box.min.z(), box.max.z());
  int near = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p(ux(rng), uy(rng), uz(rng));
    const Real d = exact.signed_distance(p).distance;
    const Real bound = field.lower_bound(p);
    ASSERT_LE(bound, d + 1e-12) << "at " << p.transpose();
    if (field.box().contains(p)) {
      ++near;
      EXPECT_GE(bound, d - std::sqrt(3.0) * field.cell_size() - 1e-6);
    }
    EXPECT_EQ(field.query(p).distance, d);
  }
  EXPECT_GT(near, 20);
}

TEST(InstrumentField, EmptyMeshIsFarEverywhere) {
  const InstrumentField field;
  EXPECT_TRUE(field.empty());
  EXPECT_TRUE(std::isinf(field.lower_bound(Vec3::Zero())));
  EXPECT_TRUE(std::isinf(field.query(Vec3::Zero()).distance));
}

/// A 2 cm cube instrument centred at the origin and a handful of loose tissue vertices (no
/// triangles: pass (a) only) of mass 1 g.
struct Cube {
  Instrument tool{make_box(0.02, 0.02, 0.02)};
  InstrumentField field{tool.local_mesh()};
  std::vector<Vec3> x, v;
  std::vector<Real> m;
  std::vector<std::uint8_t> fixed;
  ContactProjector projector;
  Grasp grasp;
  ResponseSettings settings;
  Cube(std::vector<Vec3> points) : x(std::move(points)) {
    v.assign(x.size(), Vec3::Zero());
    m.assign(x.size(), 1e-3);
    fixed.assign(x.size(), 0);
    projector.reset(x.size(), {});
    grasp.reset(x.size());
    settings.method = ResponseMethod::kSdf;
  }
  ProjectionStats step(Real dt = 1e-3) {
    const ProjectedTissue t{x, v, m, fixed, {}};
    return projector.project(tool, field, {}, 0, 1, grasp, t, 0.02, dt, settings);
  }
};

TEST(ContactProjector, VertexInsideGoesToTheNearestFacePlusTheMargin) {
  // 2 mm inside the top face (z = 0.01): out to z = 0.01 + margin, velocity Δx/dt, force
  // −m Δx/dt² on the instrument. A vertex outside is left alone.
  Cube c({Vec3(0.001, 0.002, 0.008), Vec3(0, 0, 0.02)});
  const Real margin = c.settings.contact_margin;
  const ProjectionStats s = c.step();
  EXPECT_EQ(s.projected, 1u);
  EXPECT_NEAR(c.x[0].z(), 0.01 + margin, 1e-12);
  EXPECT_NEAR(c.x[0].x(), 0.001, 1e-12);
  const Real dz = 0.002 + margin;
  EXPECT_NEAR(c.v[0].z(), dz / 1e-3, 1e-9);
  EXPECT_NEAR(s.force.z(), -1e-3 * dz / 1e-6, 1e-6);
  EXPECT_NEAR(s.max_correction, dz, 1e-12);
  EXPECT_EQ(c.x[1], Vec3(0, 0, 0.02));
  EXPECT_EQ(c.v[1], Vec3::Zero());
}

TEST(ContactProjector, FixedVerticesNeverMove) {
  Cube c({Vec3(0, 0, 0.009)});
  c.fixed[0] = 1;
  c.step();
  EXPECT_EQ(c.x[0], Vec3(0, 0, 0.009));
}

TEST(ContactProjector, AVertexPastTheMiddleLeavesBySideItCameIn) {
  // Last step just above the top face; now 1.5 cm down (past the middle, z = −0.005: the
  // bottom face is nearer). The previous-plane rule takes it back over the top, not out the
  // bottom (no friction, to check the normal part alone).
  Cube c({Vec3(0.002, 0, 0.0102)});
  c.settings.friction_static = 0;
  c.step();
  EXPECT_NEAR(c.x[0].z(), 0.0102, 1e-12);  // outside: untouched, recorded
  c.x[0].z() = -0.005;
  c.step();
  EXPECT_NEAR(c.x[0].z(), 0.01 + c.settings.contact_margin, 1e-12);
  // Without history (a fresh projector) the nearest face is the bottom one.
  Cube fresh({Vec3(0.002, 0, -0.005)});
  fresh.step();
  EXPECT_NEAR(fresh.x[0].z(), -0.01 - fresh.settings.contact_margin, 1e-12);
}

TEST(ContactProjector, FrictionSticksBelowTheConeAndSlidesAboveIt) {
  // Resting just above the top face, then moved 1.1 mm in and 0.3 mm or 1 mm sideways relative to
  // the tool: the normal correction is 1 mm + margin = 1.05 mm; 0.3 ≤ μs·1.05 = 0.63 mm sticks
  // (x back where it was); 1 mm > 0.63 mm slides, shortened by μk·1.05 mm.
  Cube c({Vec3(0.001, 0, 0.0101), Vec3(-0.001, 0, 0.0101)});
  c.settings.contact_margin = 5e-5;
  c.settings.friction_static = 0.6;
  c.settings.friction_kinetic = 0.4;
  c.step();
  const Real start0 = c.x[0].x(), start1 = c.x[1].x();
  c.x[0] += Vec3(0.0003, 0, -0.0011);  // from z = 0.0101 to 0.009
  c.x[1] += Vec3(0.001, 0, -0.0011);
  c.step();
  const Real dn = 0.001 + 5e-5;
  EXPECT_NEAR(c.x[0].x(), start0, 1e-12);
  EXPECT_NEAR(c.x[1].x(), start1 + 0.001 - 0.4 * dn, 1e-12);
  EXPECT_NEAR(c.x[0].z(), 0.01 + 5e-5, 1e-12);
  EXPECT_NEAR(c.x[1].z(), 0.01 + 5e-5, 1e-12);
}

TEST(ContactProjector, AMovingToolCarriesTheVertexAlongItsNormal) {
  // The cube moves up 1 mm in 1 ms into a vertex resting on its top face: the vertex ends on the
  // face again with the tool's velocity (1 m/s) along the normal, whatever max_force says.
  for (Real max_force : {0.001, 1000.0}) {
    Cube c({Vec3(0, 0, 0.01 + 5e-5)});
    c.settings.max_force = max_force;
    c.step();
    Pose p;
    p.translation = Vec3(0, 0, 0.001);
    c.tool.move_to(p, 1e-3);
    const ProjectionStats s = c.step();
    EXPECT_NEAR(c.x[0].z(), 0.011 + 5e-5, 1e-12) << max_force;
    EXPECT_NEAR(c.v[0].z(), 1.0, 1e-9) << max_force;
    EXPECT_NEAR(s.force.z(), -1e-3 * 0.001 / 1e-6, 1e-6) << max_force;
  }
}

TEST(ContactProjector, AThinTipBetweenCoarseVerticesPushesTheFaceAway) {
  // A 1 mm cube pressed 0.5 mm into the middle of one big tissue triangle (no tissue vertex
  // inside the tool): pass (b) moves the triangle down until the tool's lowest vertices are the
  // margin above it.
  Instrument tool(make_box(0.001, 0.001, 0.001));
  Pose p;
  p.translation = Vec3(0, 0, 0.0005 - 0.0005);  // bottom face at z = −0.0005
  tool.reset_pose(p);
  const InstrumentField field(tool.local_mesh());
  std::vector<Vec3> x = {Vec3(-0.05, -0.05, 0), Vec3(0.05, -0.05, 0), Vec3(0, 0.05, 0)};
  std::vector<Vec3> v(3, Vec3::Zero());
  std::vector<Real> m(3, 1e-3);
  std::vector<std::uint8_t> fixed(3, 0);
  const std::vector<Triangle> tris = {{0, 1, 2}};
  std::vector<Contact> contacts;
  for (std::uint32_t a = 0; a < tool.triangles().size(); ++a) {
    Contact c;
    c.kind = ContactKind::kInstrumentTissue;
    c.object_a = 0;
    c.object_b = 1;
    c.triangle_a = a;
    c.triangle_b = 0;
    contacts.push_back(c);
  }
  ContactProjector projector;
  projector.reset(3, tris);
  Grasp grasp;
  grasp.reset(3);
  ResponseSettings settings;
  const ProjectedTissue t{x, v, m, fixed, tris};
  const ProjectionStats s = projector.project(tool, field, contacts, 0, 1, grasp, t, 0.001, 1e-3, settings);
  EXPECT_GT(s.face_pushes, 0u);
  // The plane under the tool now lies at or below z = −0.0005 − margin at the tool's centre
  // (the face is interpolated at (0, 0) with that point's barycentric weights).
  const Vec3 w0 = barycentric(Vec3::Zero(), Vec3(-0.05, -0.05, 0), Vec3(0.05, -0.05, 0), Vec3(0, 0.05, 0));
  const Real z_mid = w0[0] * x[0].z() + w0[1] * x[1].z() + w0[2] * x[2].z();
  EXPECT_LE(z_mid, -0.0005 - settings.contact_margin + 1e-9);
  EXPECT_GE(z_mid, -0.0005 - settings.contact_margin - 0.0002);
}

}  // namespace
}  // namespace trocar
