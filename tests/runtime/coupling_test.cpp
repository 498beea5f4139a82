// Virtual coupling, local contact model, force shaping and timing histograms, against values
// worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "trocar/core/error.h"
#include "trocar/runtime/coupling.h"
#include "trocar/runtime/histogram.h"
#include "trocar/runtime/local_contact_model.h"

namespace trocar {
namespace {

TEST(Passivity, BoundIsTwiceDeviceMinusCouplingDampingOverPeriod) {
  // b = 2 N·s/m, B = 0.5 N·s/m, T = 1 ms: K < 2·1.5/0.001 = 3000 N/m; at 4 kHz 12000 N/m.
  EXPECT_DOUBLE_EQ(passivity_stiffness_bound(2.0, 0.5, 1e-3), 3000.0);
  EXPECT_DOUBLE_EQ(passivity_stiffness_bound(2.0, 0.5, 2.5e-4), 12000.0);
  EXPECT_NO_THROW(check_coupling_passivity({2999, 0.5}, 2.0, 1e-3, "s.json: instruments[0].device.coupling"));
  try {
    check_coupling_passivity({3000, 0.5}, 2.0, 1e-3, "s.json: instruments[0].device.coupling");
    FAIL() << "K = 3000 N/m at the bound must be rejected";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("s.json: instruments[0].device.coupling"), std::string::npos) << m;
    EXPECT_NE(m.find("3000 N/m"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(check_coupling_passivity({3000, 0.5}, 2.0, 2.5e-4, "x"));  // fine at 4 kHz
  EXPECT_THROW(check_coupling_passivity({100, 2.0}, 2.0, 1e-3, "x"), Error);  // B ≥ b: no K is passive
  EXPECT_THROW(check_coupling_passivity({-1, 0.5}, 2.0, 1e-3, "x"), Error);
  EXPECT_THROW(check_coupling_passivity({NAN, 0.5}, 2.0, 1e-3, "x"), Error);
}

LocalContactModel press_model() {
  LocalContactModel m;  // 1 N up at the origin, normal +z, k = 1000 N/m
  m.position0 = Vec3::Zero();
  m.force0 = Vec3(0, 0, 1);
  m.normal = Vec3(0, 0, 1);
  m.stiffness = 1000;
  m.in_contact = true;
  return m;
}

TEST(CoupledForce, SeriesStiffnessExtrapolatesAlongTheNormal) {
  const LocalContactModel m = press_model();
  // At the pose physics stepped: physics' own force.
  EXPECT_NEAR((coupled_force(m, 1000, Vec3::Zero()) - Vec3(0, 0, 1)).norm(), 0, 1e-12);
  // 1 mm deeper: k_s = 1000·1000/2000 = 500 N/m → 1 + 0.5 = 1.5 N.
  EXPECT_NEAR(coupled_force(m, 1000, Vec3(0, 0, -0.001)).z(), 1.5, 1e-12);
  // Sideways motion changes nothing (the Jacobian is −k n nᵀ).
  EXPECT_NEAR((coupled_force(m, 1000, Vec3(0.003, -0.002, 0)) - Vec3(0, 0, 1)).norm(), 0, 1e-12);
  // 1.5 mm up: 1 − 0.75 = 0.25 N; 3 mm up the tissue would pull: 0.
  EXPECT_NEAR(coupled_force(m, 1000, Vec3(0, 0, 0.0015)).z(), 0.25, 1e-12);
  EXPECT_EQ(coupled_force(m, 1000, Vec3(0, 0, 0.003)), Vec3::Zero());
  // A rigid organ (k → ∞) renders the coupling's K and no more.
  LocalContactModel rigid = m;
  rigid.stiffness = 1e12;
  EXPECT_NEAR(coupled_force(rigid, 1000, Vec3(0, 0, -0.001)).z(), 2.0, 1e-6);
  LocalContactModel free;
  EXPECT_EQ(coupled_force(free, 1000, Vec3(0, 0, -0.01)), Vec3::Zero());
}

TEST(LocalContactModel, ForceAtHoldsTangentialFrictionAndNeverPulls) {
  LocalContactModel m = press_model();
  m.force0 = Vec3(0.3, 0, 1);  // friction 0.3 N along x
  m.normal = Vec3(0, 0, 1);
  EXPECT_NEAR((m.force_at(Vec3(0, 0, -0.002)) - Vec3(0.3, 0, 3)).norm(), 0, 1e-12);
  EXPECT_EQ(m.force_at(Vec3(0, 0, 0.0011)), Vec3::Zero());
}

TEST(ContactStiffnessEstimator, SecantOfALinearContactIsItsStiffness) {
  ContactStiffnessEstimator e(500);
  // F = 800 (0.01 − z) along +z for z < 0.01: pressed from 9 mm to 5 mm in 0.1 mm steps.
  LocalContactModel m;
  for (int i = 0; i <= 40; ++i) {
    const double z = 0.009 - 1e-4 * i;
    m = e.update(Vec3(0, 0, z), Vec3(0, 0, 800 * (0.01 - z)));
    if (i == 0) {
      EXPECT_DOUBLE_EQ(m.stiffness, 500);  // the prior until a secant exists
    }
  }
  EXPECT_NEAR(m.stiffness, 800, 1e-6);
  EXPECT_TRUE(m.in_contact);
  EXPECT_NEAR((m.normal - Vec3(0, 0, 1)).norm(), 0, 1e-12);
  // Moves below kMinMove do not take a secant (the anchor stays): still 800 after noise.
  m = e.update(Vec3(0, 0, 0.005 - 1e-6), Vec3(0, 0, 3.9));
  EXPECT_NEAR(m.stiffness, 800, 1e-6);
  // Losing the contact forgets the estimate.
  m = e.update(Vec3(0, 0, 0.02), Vec3::Zero());
  EXPECT_FALSE(m.in_contact);
  m = e.update(Vec3(0, 0, 0.009), Vec3(0, 0, 0.8));
  EXPECT_DOUBLE_EQ(m.stiffness, 500);
}

TEST(ForceShaper, ClampsSlewLimitsAndStartsSafely) {
  ForceShaping s;
  s.max_force = 3;
  s.slew_rate = 1000;  // 1 N per 1 ms tick
  s.engage_below = 0.2;
  s.ramp_time = 0.01;  // 10 ticks
  ForceShaper f(s);
  const double T = 1e-3;
  // Connected while pressing 2 N: nothing until the force falls below 0.2 N.
  for (int i = 0; i < 5; ++i) EXPECT_EQ(f.shape(Vec3(0, 0, 2), T), Vec3::Zero());
  EXPECT_FALSE(f.engaged());
  EXPECT_NEAR(f.shape(Vec3(0, 0, 0.1), T).z(), 0.1 * 0.1, 1e-12);  // ramp 1/10
  EXPECT_TRUE(f.engaged());
  for (int i = 2; i <= 10; ++i) EXPECT_NEAR(f.shape(Vec3(0, 0, 0.1), T).z(), 0.1 * i / 10.0, 1e-12);
  // Fully on: a step to 10 N is clamped to 3 N and reached at 1 N per tick.
  EXPECT_NEAR(f.shape(Vec3(0, 0, 10), T).z(), 1.1, 1e-12);
  EXPECT_NEAR(f.shape(Vec3(0, 0, 10), T).z(), 2.1, 1e-12);
  EXPECT_NEAR(f.shape(Vec3(0, 0, 10), T).z(), 3.0, 1e-12);
  EXPECT_NEAR(f.shape(Vec3(0, 0, 10), T).z(), 3.0, 1e-12);
  // NaN in, zero out; disengage is immediate.
  f.disengage();
  EXPECT_EQ(f.shape(Vec3(NAN, 0, 0), T), Vec3::Zero());
}

TEST(TimingHistogram, QuantilesWithinABinOfTheTruth) {
  TimingHistogram h;
  for (int i = 1; i <= 1000; ++i) h.add(double(i));  // 1 … 1000 µs
  EXPECT_EQ(h.count(), 1000u);
  EXPECT_DOUBLE_EQ(h.max(), 1000.0);
  EXPECT_NEAR(h.mean(), 500.5, 1e-9);
  EXPECT_NEAR(h.median(), 500, 500 * 0.012);
  EXPECT_NEAR(h.p99(), 990, 990 * 0.012);
  EXPECT_NEAR(double(h.count_above(900)), 100, 12);  // within one bin (1.2 % of 900)
  TimingHistogram g;
  g.add(5e6);  // above the range: last bin, max exact
  g.merge(h);
  EXPECT_EQ(g.count(), 1001u);
  EXPECT_DOUBLE_EQ(g.max(), 5e6);
  EXPECT_EQ(TimingHistogram().quantile(0.5), 0.0);
}

}  // namespace
}  // namespace trocar
