// ResponseSolver: many contacts per step, sums, Jacobians, clamp, grasp, corrections.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "trocar/geometry/triangle_triangle.h"
#include "trocar/mesh/generate.h"
#include "trocar/response/response_solver.h"

namespace trocar {
namespace {

// Brute-force instrument(0)–tissue(1) contacts, in contact order.
std::vector<Contact> brute_contacts(const Instrument& tool, const TriMesh& tissue) {
  std::vector<Contact> out;
  const auto ix = tool.world_positions();
  for (std::uint32_t i = 0; i < tool.triangles().size(); ++i) {
    const Triangle& a = tool.triangles()[i];
    for (std::uint32_t j = 0; j < tissue.triangles.size(); ++j) {
      const auto b = tissue.corners(j);
      const TriTriResult r = intersect_triangles(ix[a[0]], ix[a[1]], ix[a[2]], b[0], b[1], b[2]);
      if (!r.intersects) continue;
      Contact c;
      c.object_a = 0;
      c.object_b = 1;
      c.triangle_a = i;
      c.triangle_b = j;
      c.coplanar = r.coplanar;
      c.segment_p = r.p;
      c.segment_q = r.q;
      out.push_back(c);
    }
  }
  return out;
}

struct Fixture {
  // A 2 cm cube (top vertex: +z, above the sheet) half through a flat 10 cm sheet (n_out = +z)
  // with 1 cm cells, moving down at 1 m/s (0.5 mm in 0.5 ms).
  Instrument tool{make_box(0.02, 0.02, 0.02), Vec3(0, 0, 1)};
  TriMesh sheet = make_sheet(0.1, 0.1, 10, 10);
  std::vector<Vec3> velocities = std::vector<Vec3>(sheet.positions.size(), Vec3::Zero());
  TissueLoads loads;
  InstrumentLoad load;
  Fixture() {
    tool.reset_pose(Pose::from_euler_deg(Vec3(0.0013, 0.0021, 0.0005), Vec3(0, 0, 0)));
    tool.move_to(Pose::from_euler_deg(Vec3(0.0013, 0.0021, 0.0), Vec3(0, 0, 0)), 5e-4);
    loads.reset(sheet.positions.size());
  }
  TissueView view() const { return {sheet.positions, velocities, sheet.triangles}; }
};

TEST(ResponseSolver, ForcesSumOppositeToInstrumentAndJacobians) {
  Fixture f;
  const std::vector<Contact> contacts = brute_contacts(f.tool, f.sheet);
  ASSERT_GT(contacts.size(), 10u);
  ResponseSettings s;
  s.method = ResponseMethod::kObb;  // the seed's kernel (the default is sdf)
  ResponseSolver solver(s);
  solver.reset(f.sheet.positions.size());
  const ResponseStats st = solver.apply(contacts, 0, 1, f.tool, f.view(), f.loads, f.load);
  EXPECT_EQ(st.considered, contacts.size());
  const std::uint32_t applied = st.count(ContactStatus::kApplied);
  EXPECT_GT(applied, 0u);
  EXPECT_EQ(st.count(ContactStatus::kPierced), 0u);
  // Recompute each contact with the kernel: Σ F, Σ (P − o) × (−F).
  Vec3 sum_f = Vec3::Zero(), sum_t = Vec3::Zero();
  std::size_t with_force = 0;
  for (const Contact& c : contacts) {
    ContactTriangles t;
    for (int i = 0; i < 3; ++i) {
      t.a[i] = f.tool.world_positions()[f.tool.triangles()[c.triangle_a][i]];
      t.va[i] = f.tool.velocity_at(t.a[i]);
      t.b[i] = f.sheet.positions[f.sheet.triangles[c.triangle_b][i]];
      t.vb[i] = Vec3::Zero();
    }
    const ContactResponse r = respond_contact(t, f.tool.world_obb(), &f.tool.top_world(), {}, s);
    if (r.status != ContactStatus::kApplied) continue;
    EXPECT_LE(r.force.dot(Vec3::UnitZ()), 0.0);  // never out of the tissue
    sum_f += r.force;
    sum_t += (r.point - f.tool.pose().translation).cross(-r.force);
    with_force += r.force.squaredNorm() > 0;
  }
  Vec3 tissue_total = Vec3::Zero();
  for (const Vec3& x : f.loads.forces()) tissue_total += x;
  EXPECT_LT((tissue_total - sum_f).norm(), 1e-9 * sum_f.norm());
  EXPECT_LT((f.load.raw_force + tissue_total).norm(), 1e-9 * sum_f.norm());
  EXPECT_LT((f.load.raw_torque - sum_t).norm(), 1e-9 * sum_t.norm() + 1e-15);
  EXPECT_EQ(f.loads.contacts.size(), with_force);
  for (const ContactJacobian& j : f.loads.contacts) {
    EXPECT_NEAR(j.weights[0] + j.weights[1] + j.weights[2], 1.0, 1e-12);
    EXPECT_LT((j.normal - Vec3(0, 0, -1)).norm(), 1e-12);
    EXPECT_EQ(j.stiffness, s.stiffness);
    EXPECT_EQ(j.damping, s.damping);
  }
  // Clamped for the device: |force| = max_force, same direction, torque scaled alike.
  EXPECT_TRUE(f.load.clamped);
  EXPECT_NEAR(f.load.force.norm(), s.max_force, 1e-12);
  EXPECT_GT(f.load.force.z(), 0);
  const Real k = s.max_force / f.load.raw_force.norm();
  EXPECT_LT((f.load.torque - k * f.load.raw_torque).norm(), 1e-15);
}

TEST(ResponseSolver, GraspedVerticesFollowTheInstrument) {
  Fixture f;
  std::vector<std::uint32_t> all(f.tool.triangles().size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  f.tool.set_jaw_triangles(all);
  f.tool.set_jaw(1.0);
  const std::vector<Contact> contacts = brute_contacts(f.tool, f.sheet);
  ResponseSolver solver;
  solver.reset(f.sheet.positions.size());
  const ResponseStats st = solver.apply(contacts, 0, 1, f.tool, f.view(), f.loads, f.load);
  EXPECT_EQ(st.count(ContactStatus::kGrasped), contacts.size());
  EXPECT_EQ(st.count(ContactStatus::kApplied), 0u);
  for (const Vec3& x : f.loads.forces()) EXPECT_EQ(x, Vec3::Zero());  // no penalty for held tissue
  EXPECT_EQ(f.load.raw_force, Vec3::Zero());
  const auto held = solver.grasp().held();
  ASSERT_GT(held.size(), 3u);
  // Each held vertex keeps its instrument-frame position local = pose₀⁻¹(x₀) through 5 moves.
  const Pose pose0 = f.tool.pose();
  std::vector<Vec3> local;
  for (const GraspedVertex& g : held) local.push_back(pose0.inverse().apply(f.sheet.positions[g.vertex]));
  for (int k = 1; k <= 5; ++k) {
    const Pose pk = Pose::from_euler_deg(Vec3(0.002 * k, -0.001 * k, 0.004 * k), Vec3(3.0 * k, 0, 10.0 * k));
    f.tool.move_to(pk, 1e-3);
    solver.apply_grasp(f.tool, f.sheet.positions, f.velocities);
    for (std::size_t i = 0; i < held.size(); ++i) {
      const Vec3 x = f.sheet.positions[held[i].vertex];
      EXPECT_LT((x - pk.apply(local[i])).norm(), 1e-12);
      EXPECT_LT((f.velocities[held[i].vertex] - f.tool.velocity_at(x)).norm(), 1e-12);
    }
  }
  // Opening the jaws releases everything.
  f.tool.set_jaw(0.0);
  f.loads.clear();
  f.load.clear();
  solver.apply({}, 0, 1, f.tool, f.view(), f.loads, f.load);
  EXPECT_TRUE(solver.grasp().held().empty());
}

TEST(ResponseSolver, ProjectAppliesDeformationAsPositionCorrection) {
  // One contact, method project: vertices move by w_i·D (Σw = 1 < max(1, ·)).
  Fixture f;
  const std::vector<Contact> contacts = brute_contacts(f.tool, f.sheet);
  ResponseSettings s;
  s.method = ResponseMethod::kProject;
  ResponseSolver solver(s);
  solver.reset(f.sheet.positions.size());
  const std::span<const Contact> one(contacts.data(), 1);
  const ResponseStats st = solver.apply(one, 0, 1, f.tool, f.view(), f.loads, f.load);
  ASSERT_EQ(st.count(ContactStatus::kApplied), 1u);
  const ContactResponse r = solver.last();
  const Triangle tb = f.sheet.triangles[contacts[0].triangle_b];
  const std::vector<Vec3> before = f.sheet.positions;
  solver.apply_corrections(f.sheet.positions);
  for (int i = 0; i < 3; ++i)
    EXPECT_LT((f.sheet.positions[tb[i]] - before[tb[i]] - r.weights_b[i] * r.deformation).norm(), 1e-15);
  // obb does not correct positions.
  ResponseSolver plain;
  plain.reset(f.sheet.positions.size());
  plain.apply(one, 0, 1, f.tool, f.view(), f.loads, f.load);
  const std::vector<Vec3> now = f.sheet.positions;
  plain.apply_corrections(f.sheet.positions);
  EXPECT_EQ(now, f.sheet.positions);
}

TEST(ResponseSolver, CorrectionGateByHand) {
  EXPECT_DOUBLE_EQ(correction_gate(0.025, 0.05), 0.5);
  EXPECT_DOUBLE_EQ(correction_gate(0.01, 0.04), 0.25);
  EXPECT_EQ(correction_gate(0.05, 0.05), 1.0);
  EXPECT_EQ(correction_gate(2.0, 0.05), 1.0);     // saturates
  EXPECT_EQ(correction_gate(0.0, 0.05), 0.0);     // resting
  EXPECT_EQ(correction_gate(-0.3, 0.05), 0.0);    // withdrawing
  EXPECT_EQ(correction_gate(-0.3, 0.0), 1.0);     // ungated
}

/// The correction of the first contact when the cube arrives at the fixture's pose moving down
/// (into the sheet, n_in = −z) at `down` m/s, and |w_i D| for comparison.
struct GatedCorrection {
  Real moved = 0;     ///< largest |Δx| of the contact triangle's vertices
  Real expected = 0;  ///< largest |w_i D|
};
GatedCorrection gated_correction(Real down, Real correction_speed) {
  Fixture f;
  const Real dt = 5e-4;
  const Vec3 at(0.0013, 0.0021, 0.0);
  f.tool.reset_pose(Pose::from_euler_deg(at + Vec3(0, 0, down * dt), Vec3(0, 0, 0)));
  f.tool.move_to(Pose::from_euler_deg(at, Vec3(0, 0, 0)), dt);
  const std::vector<Contact> contacts = brute_contacts(f.tool, f.sheet);
  ResponseSettings s;
  s.method = ResponseMethod::kProject;
  s.correction_speed = correction_speed;
  ResponseSolver solver(s);
  solver.reset(f.sheet.positions.size());
  const std::span<const Contact> one(contacts.data(), 1);
  EXPECT_EQ(solver.apply(one, 0, 1, f.tool, f.view(), f.loads, f.load).count(ContactStatus::kApplied), 1u);
  const ContactResponse r = solver.last();
  const Triangle tb = f.sheet.triangles[contacts[0].triangle_b];
  const std::vector<Vec3> before = f.sheet.positions;
  solver.apply_corrections(f.sheet.positions);
  GatedCorrection g;
  for (int i = 0; i < 3; ++i) {
    g.moved = std::max(g.moved, (f.sheet.positions[tb[i]] - before[tb[i]]).norm());
    g.expected = std::max(g.expected, (r.weights_b[i] * r.deformation).norm());
  }
  return g;
}

TEST(ResponseSolver, CorrectionIsGatedByTheInstrumentsApproach) {
  // Driving in at half the gate speed: half the correction; at 1 m/s: all of it; held still or
  // withdrawing: none (the penalty force alone answers, so a held instrument settles).
  const GatedCorrection half = gated_correction(0.025, 0.05);
  ASSERT_GT(half.expected, 1e-5);
  EXPECT_NEAR(half.moved, 0.5 * half.expected, 1e-15);
  const GatedCorrection fast = gated_correction(1.0, 0.05);
  EXPECT_NEAR(fast.moved, fast.expected, 1e-15);
  EXPECT_EQ(gated_correction(0.0, 0.05).moved, 0.0);
  EXPECT_EQ(gated_correction(-0.2, 0.05).moved, 0.0);
  // Ungated (correction_speed 0): the full correction whatever the motion.
  const GatedCorrection still = gated_correction(0.0, 0.0);
  ASSERT_GT(still.expected, 1e-5);
  EXPECT_NEAR(still.moved, still.expected, 1e-15);
}

TEST(ResponseSolver, SkipsOtherPairsAndKinds) {
  Fixture f;
  std::vector<Contact> contacts = brute_contacts(f.tool, f.sheet);
  for (Contact& c : contacts) c.object_b = 2;
  ResponseSolver solver;
  solver.reset(f.sheet.positions.size());
  const ResponseStats st = solver.apply(contacts, 0, 1, f.tool, f.view(), f.loads, f.load);
  EXPECT_EQ(st.considered, 0u);
  EXPECT_EQ(f.load.raw_force, Vec3::Zero());
}

}  // namespace
}  // namespace trocar
