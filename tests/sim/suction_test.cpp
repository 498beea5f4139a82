// A suction-irrigator's valves through the simulation (docs/electrosurgery.md, "Suction and
// irrigation"): they open only on an instrument that has them, shut when it leaves through its
// port, and reach the renderer's snapshot with the tip and the direction the cannula points.
#include <gtest/gtest.h>

#include <numbers>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"
#include "trocar/sim/view_snapshot.h"

namespace trocar {
namespace {

World cannula_and_hook() {
  World world;
  world.add_tissue("sheet", make_sheet(0.05, 0.05, 10, 10), material_preset("peritoneum"), FixedSelection{},
                   Vec3(0, 0, -9.81), IntegratorKind::kXpbd);
  // The cannula 2 cm above the sheet, tilted 30° about x: it points down and towards −y.
  const Quat tilt(Eigen::AngleAxis<Real>(std::numbers::pi / 6, Vec3::UnitX()));
  const InstrumentMesh cannula = make_suction_irrigator();
  InstrumentBody& c = world.add_instrument("cannula", Instrument(cannula.mesh, Vec3::UnitZ()),
                                           KeyframeMotion({{0, Vec3(0, 0, 0.02), tilt, 0}}));
  c.tool = "suction-irrigator";
  c.suction = SuctionSpec{};
  c.port = "right";
  // The hook shares its port and has no valves.
  const InstrumentMesh hook = make_hook_probe();
  InstrumentBody& h = world.add_instrument("hook", Instrument(hook.mesh, Vec3::UnitZ()),
                                           KeyframeMotion({{0, Vec3(0, 0, 0.02), tilt, 0}}));
  h.tool = "hook-probe";
  h.port = "right";
  return world;
}

TEST(Suction, ValvesOpenOnlyOnACannulaAndReachTheSnapshotWithItsTipAndAim) {
  Simulation sim(cannula_and_hook(), SimulationSettings{});
  EXPECT_EQ(sim.world().instruments[1].suction.any(), false);  // an instrument built without it has none
  sim.set_suction(0, true);
  sim.set_irrigation(0, true);
  sim.set_suction(1, true);
  sim.set_irrigation(1, true);
  EXPECT_TRUE(sim.suction_on(0));
  EXPECT_TRUE(sim.irrigation_on(0));
  EXPECT_FALSE(sim.suction_on(1));
  EXPECT_FALSE(sim.irrigation_on(1));
  sim.step(1e-3);
  ViewSnapshot snap;
  capture_view(sim, snap);
  const InstrumentView& v = snap.instruments[0];
  EXPECT_TRUE(v.suction);
  EXPECT_TRUE(v.irrigation);
  EXPECT_FALSE(snap.instruments[1].suction);
  EXPECT_LT((v.tip - Vec3(0, 0, 0.02)).norm(), 1e-12);
  // Its shaft runs along local +z from the tip: it points along −z turned 30° about x,
  // (0, sin 30°, −cos 30°).
  EXPECT_LT((v.forward - Vec3(0, 0.5, -std::sqrt(3.0) / 2)).norm(), 1e-9);
  EXPECT_EQ(v.suction_spec.suction_flow, SuctionSpec{}.suction_flow);
  // Exchanged for the hook: the cannula leaves with its valves shut.
  sim.exchange(0);
  EXPECT_FALSE(sim.suction_on(0));
  EXPECT_FALSE(sim.irrigation_on(0));
  for (int k = 0; k < 3; ++k) sim.step(1e-3);
  capture_view(sim, snap);
  EXPECT_FALSE(snap.instruments[0].suction);
  EXPECT_FALSE(snap.instruments[0].irrigation);
}

}  // namespace
}  // namespace trocar
