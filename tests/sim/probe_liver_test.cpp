// Developer scene with the real shared meshes (skipped when ../shared is absent): the hook probe
// presses on the liver and holds; with the seed's `obb` response (and its depth cap) the run stays
// stable, makes contacts and a force pushing the probe back, and the liver settles. Without the
// cap the held probe kept liver vertices jittering at 1–2 m/s (docs/response.md, "Depth cap").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "probe_liver_scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

TEST(ProbeLiver, PressStaysStableWithContactsAndUpwardForce) {
  const auto text = test::probe_liver_scene_text(0.5, "obb");
  if (!text) GTEST_SKIP() << "shared meshes absent";
  Scene scene = parse_scene(*text, "probe-liver.json", "/");
  Simulation sim(std::move(scene.world), scene.settings);
  std::uint32_t max_contacts = 0, late_min_contacts = 1u << 30;
  Real max_depth = 0, max_force_z = 0, late_speed = 0;
  for (int n = 0; n < 1500; ++n) {
    const StepMetrics& m = sim.step(1e-3);
    ASSERT_TRUE(m.finite) << "step " << n;
    ASSERT_LT(m.max_speed, 2.0) << "step " << n;
    max_contacts = std::max(max_contacts, m.contacts);
    max_depth = std::max(max_depth, m.penetration_max);
    max_force_z = std::max(max_force_z, sim.instrument_metrics()[0].force.z());
    if (n >= 1200) {  // held since t = 0.5 s
      late_speed = std::max(late_speed, m.max_speed);
      late_min_contacts = std::min(late_min_contacts, m.contacts);
    }
  }
  std::printf("[ probe-liver ] max contacts %u, max depth %.3f mm, max force z %.3f N, last 300 ms: fastest "
              "vertex %.4f m/s, fewest contacts %u\n",
              max_contacts, max_depth * 1e3, max_force_z, late_speed, late_min_contacts);
  EXPECT_GT(max_contacts, 0u);
  EXPECT_GT(max_force_z, 0.1);
  // Settled in steady contact (uncapped: 1–2 m/s, and steps with no contact at all).
  EXPECT_LT(late_speed, 0.05);
  EXPECT_GT(late_min_contacts, 0u);
}

}  // namespace
}  // namespace trocar
