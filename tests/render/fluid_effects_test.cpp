// Blood and saline on the render side (docs/electrosurgery.md, "Suction and irrigation"): a
// suction valve draws fluid at its flow from within its radius and smoke around its tip; an
// irrigation jet lands where the cannula points, dilutes the blood and washes its stain; what
// drips off one tissue lands on the one below. Every part conserved. No GL: EffectsView alone,
// fed snapshots built here.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/render/effects_view.h"

namespace trocar {
namespace {

constexpr Real kFrame = 1.0 / 30;

TissueModel model_of(const TriMesh& mesh) {
  TissueModel m;
  m.triangles = mesh.triangles;
  m.rest = mesh.positions;
  return m;
}

/// The vertex of `x` nearest `p`.
std::uint32_t nearest(const std::vector<Vec3>& x, const Vec3& p) {
  std::uint32_t best = 0;
  for (std::uint32_t v = 1; v < x.size(); ++v)
    if ((x[v] - p).squaredNorm() < (x[best] - p).squaredNorm()) best = v;
  return best;
}

/// A snapshot of fixed tissues at `time`, one wound per entry of `bled` (its total so far).
struct Frames {
  std::vector<TissueModel> models;
  ViewSnapshot snap;
  explicit Frames(std::vector<TriMesh> meshes) {
    for (const TriMesh& m : meshes) {
      models.push_back(model_of(m));
      snap.tissues.push_back(m.positions);
    }
    snap.tissue_effects.resize(meshes.size());
  }
  void wound(std::uint32_t tissue, std::uint32_t vertex) { snap.wounds.push_back({tissue, vertex, 0.0, true}); }
  InstrumentView& cannula(const Vec3& tip, const Vec3& forward) {
    InstrumentView v;
    v.tip = tip;
    v.forward = forward.normalized();
    snap.instruments.push_back(v);
    return snap.instruments.back();
  }
  Real advance(EffectsView& e, const EffectsSwitches& on = {}) {
    snap.time += kFrame;
    return e.update(snap, models, on);
  }
};

void expect_conserved(const EffectsView& e) {
  EXPECT_NEAR(e.blood_volume() + e.pool_blood() + e.suctioned_blood(), e.fed(), 1e-9 * e.fed());
  EXPECT_NEAR(e.volume() + e.pool() + e.suctioned(), e.fed() + e.irrigated(), 1e-9 * (e.fed() + e.irrigated()));
}

TEST(FluidEffects, SuctionDrawsFluidAtItsFlowFromWithinItsRadiusOnly) {
  // A 4 cm bowl 5 mm deep, 2 mm cells; 0.3 ml of blood bled at its bottom in the first frame
  // pools there. A cannula over the bottom draws 1 ml/s from within 5 mm of its tip.
  Frames f({make_sheet(0.04, 0.04, 20, 20, -0.005)});
  const std::uint32_t bottom = nearest(f.snap.tissues[0], Vec3(0, 0, -0.005));
  f.wound(0, bottom);
  EffectsView e;
  f.advance(e);  // the first frame sets the clock
  f.snap.wounds[0].emitted = 0.3e-6;
  f.snap.wounds[0].open = false;
  for (int k = 0; k < 30; ++k) f.advance(e);  // a second to settle
  const Real settled = e.blood_volume();
  EXPECT_NEAR(settled, 0.3e-6, 1e-15);       // a bowl keeps it all
  InstrumentView& c = f.cannula(Vec3(0, 0, -0.004), Vec3(0, 0, -1));
  c.suction_spec.suction_flow = 1e-6;
  c.suction = true;
  const auto within = [&] {
    Real v = 0;
    for (std::size_t i = 0; i < e.film(0)->size(); ++i)
      if ((f.snap.tissues[0][i] - c.tip).norm() <= c.suction_spec.suction_radius) v += e.film(0)->film()[i];
    return v;
  };
  // While there is more within reach than a frame's flow, each frame takes exactly the flow.
  for (int k = 0; k < 3; ++k) {
    const Real before = e.suctioned();
    ASSERT_GT(within(), 1e-6 * kFrame);
    f.advance(e);
    EXPECT_NEAR(e.suctioned() - before, 1e-6 * kFrame, 1e-18);
  }
  for (int k = 0; k < 60; ++k) f.advance(e);
  // The bowl drains towards the cannula; what is left lies outside its reach or in the wetting layer.
  EXPECT_LT(e.blood_volume(), 0.2 * settled);
  EXPECT_GT(e.suctioned_blood(), 0.8 * settled);
  EXPECT_EQ(e.suctioned_blood(), e.suctioned());  // no saline here
  expect_conserved(e);
  // Shut: nothing more is drawn.
  f.snap.instruments[0].suction = false;
  const Real drawn = e.suctioned();
  for (int k = 0; k < 5; ++k) f.advance(e);
  EXPECT_EQ(e.suctioned(), drawn);
}

TEST(FluidEffects, SuctionClearsTheSmokeAroundItsTipFasterThanItFades) {
  Frames with({make_sheet(0.04, 0.04, 4, 4)}), without({make_sheet(0.04, 0.04, 4, 4)});
  EffectsView a, b;
  for (Frames* f : {&with, &without}) {
    f->snap.vapour.push_back({Vec3(0, 0, 0.001), Vec3::UnitZ(), 0.0, true});
    f->cannula(Vec3(0, 0, 0.02), Vec3(0, 0, -1)).suction = f == &with;
  }
  for (int k = 0; k < 45; ++k) {
    for (Frames* f : {&with, &without}) f->snap.vapour[0].energy = k < 15 ? 0.5 * k : 7.0;  // 7 J of vapour in 0.5 s
    with.advance(a);
    without.advance(b);
  }
  ASSERT_NE(a.smoke(), nullptr);
  const Real cleared = a.smoke()->total_cover(), kept = b.smoke()->total_cover();
  std::printf("smoke cover after 1.5 s: %.3g m² with suction at the plume, %.3g without\n", cleared, kept);
  EXPECT_LT(cleared, 0.5 * kept);
}

TEST(FluidEffects, IrrigationDilutesTheBloodWashesItsStainAndRunsItOff) {
  // A 4 × 4 cm sheet tilted 20° (falling along +x); a wound near its top bleeds 0.1 ml in the
  // first 0.2 s. Then a jet from 2 cm above aims at the wound: 10 ml/s. A control without it.
  const auto tilted = [] {
    TriMesh m = make_sheet(0.04, 0.04, 20, 20);
    const Real a = 20 * std::numbers::pi / 180;
    for (Vec3& x : m.positions) x = Vec3(x.x() * std::cos(a), x.y(), -x.x() * std::sin(a));
    return m;
  };
  Frames f({tilted()}), control({tilted()});
  const std::uint32_t w = nearest(f.snap.tissues[0], Vec3(-0.015, 0, 0.005));
  for (Frames* s : {&f, &control}) s->wound(0, w);
  EffectsView e, c;
  f.advance(e);
  control.advance(c);
  for (int k = 1; k <= 6; ++k) {
    for (Frames* s : {&f, &control}) s->snap.wounds[0].emitted = 0.1e-6 * k / 6;
    f.advance(e);
    control.advance(c);
  }
  for (Frames* s : {&f, &control}) s->snap.wounds[0].open = false;
  const Vec3 at = f.snap.tissues[0][w];
  InstrumentView& jet = f.cannula(at + Vec3(0, 0, 0.02), Vec3(0, 0, -1));
  jet.suction_spec.irrigation_flow = 1e-5;
  jet.irrigation = true;
  const Real stain_before = e.film(0)->stain()[w];
  ASSERT_GT(stain_before, 0.9);
  for (int k = 0; k < 30; ++k) {
    f.advance(e);
    control.advance(c);
  }
  EXPECT_NEAR(e.irrigated(), 30 * 1e-5 * kFrame, 1e-15);
  {
    const BloodFilm& g = *e.film(0);
    for (int i = 0; i <= 20; ++i) {
      const std::uint32_t v = nearest(f.snap.tissues[0], Vec3(-0.02 + 0.002 * i, 0, 0) );
      std::printf("%.2f ", 1e3 * g.thickness(v));
    }
    std::printf(" mm; substeps %d\n", g.last_substeps());
  }
  const BloodFilm& film = *e.film(0);
  // The jet landed at the wound (within its radius of the axis): saline there.
  EXPECT_GT(film.film()[w], film.blood()[w]);
  std::printf("after 1 s of irrigation: stain at the wound %.3f (was %.3f; %.3f without), blood on the sheet "
              "%.3g ml (%.3g ml without), saline %.3g ml\n", film.stain()[w], stain_before, c.film(0)->stain()[w],
              1e6 * e.blood_volume(), 1e6 * c.blood_volume(), 1e6 * (e.volume() - e.blood_volume()));
  EXPECT_LT(film.stain()[w], 0.5 * stain_before);       // washed
  EXPECT_GT(c.film(0)->stain()[w], 0.9);                 // the control keeps its stain
  EXPECT_LT(e.blood_volume(), 0.5 * c.blood_volume());   // flushed off the sheet
  expect_conserved(e);
  expect_conserved(c);
  // A jet aimed at nothing (up, away from the sheet) is still counted: into the pool.
  f.snap.instruments[0].forward = Vec3(0, 0, 1);
  const Real pool = e.pool(), irrigated = e.irrigated();
  f.advance(e);
  EXPECT_NEAR(e.irrigated() - irrigated, 1e-5 * kFrame, 1e-18);
  EXPECT_GE(e.pool() - pool, 1e-5 * kFrame * (1 - 1e-9));
  expect_conserved(e);
}

TEST(FluidEffects, BloodDrippingOffOneTissueLandsOnTheTissueBelowAndIsDrawnThere) {
  // A ceiling sheet facing down 3 cm above a floor bowl, and a third sheet off to the side. A
  // wound on the ceiling bleeds 0.2 ml: beyond what surface tension holds under a ceiling, it
  // drips onto the floor.
  TriMesh ceiling = make_sheet(0.02, 0.02, 10, 10);
  for (Vec3& x : ceiling.positions) x.z() = 0.03;
  for (Triangle& t : ceiling.triangles) std::swap(t[1], t[2]);  // facing down
  TriMesh aside = make_sheet(0.02, 0.02, 10, 10);
  for (Vec3& x : aside.positions) x.x() += 0.1;
  Frames f({ceiling, make_sheet(0.04, 0.04, 20, 20, -0.004), aside});
  f.wound(0, nearest(f.snap.tissues[0], Vec3(0, 0, 0.03)));
  EffectsView e;
  f.advance(e);
  for (int k = 1; k <= 10; ++k) {
    f.snap.wounds[0].emitted = 0.2e-6 * k / 10;
    f.advance(e);
  }
  std::printf("ceiling %.3g ml, floor %.3g ml, pool %.3g ml of %.3g ml bled\n", 1e6 * e.film(0)->blood_volume(),
              1e6 * e.film(1)->blood_volume(), 1e6 * e.pool_blood(), 1e6 * e.fed());
  EXPECT_GT(e.film(1)->blood_volume(), 0.5 * e.fed());  // most fell onto the floor
  EXPECT_EQ(e.film(2)->volume(), 0.0);
  EXPECT_LT(e.pool_blood(), 1e-3 * e.fed());            // nothing missed the floor
  expect_conserved(e);
  std::vector<float> out;
  EXPECT_TRUE(e.fill(f.snap, 1, f.snap.tissues[1].size(), true, out));   // the floor is drawn bloody
  EXPECT_FALSE(e.fill(f.snap, 2, f.snap.tissues[2].size(), true, out));  // the untouched sheet is not
}

}  // namespace
}  // namespace trocar
