// Every scene shipped in scenes/ loads (generated geometry only: a user's clone has no
// ../shared) and runs 2 s of simulated time stably; the stab scene applies no far-surface
// contact (the pierced-organ filter, step 9 of docs/response.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trocar/response/contact_response.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

const std::string kScenes = TROCAR_SCENES_DIR;

/// What a 2 s run of a scene showed.
struct RunSummary {
  bool stable = true;            ///< every step's state stable (core/stability.h)
  Real max_kinetic = 0;          ///< J
  Real max_speed = 0;            ///< fastest tissue vertex (m/s)
  Real max_penetration = 0;      ///< m
  std::uint64_t contacts = 0;    ///< Σ contacts over steps
  std::uint64_t applied = 0;     ///< Σ applied contacts
  std::uint64_t tunneling = 0;   ///< Σ tunneling events
  std::uint64_t far_contacts = 0;          ///< contacts whose tissue plane has the top vertex behind it
  std::uint64_t far_contacts_applied = 0;  ///< of those, ones the kernel would apply (must be 0)
};

/// True when the instrument's top vertex lies behind the tissue triangle's plane (inside the
/// organ as seen from that triangle): a far-surface contact, which step 9 discards.
bool far_surface(const Vec3& top, const std::array<Vec3, 3>& b) {
  const Vec3 n = (b[1] - b[0]).cross(b[2] - b[0]);
  return n.dot(top - b[0]) < 0;
}

RunSummary run_scene(const std::string& file, Real seconds) {
  Scene scene = load_scene(kScenes + "/" + file);
  const ResponseSettings response = scene.settings.response;
  Simulation sim = make_simulation(scene);
  RunSummary out;
  out.stable = drive(sim, scene.timestep, step_count(seconds, scene.timestep), [&](const StepMetrics& m) {
    out.max_kinetic = std::max(out.max_kinetic, m.kinetic_energy);
    out.max_speed = std::max(out.max_speed, m.max_speed);
    out.max_penetration = std::max(out.max_penetration, m.penetration_max);
    out.contacts += m.contacts;
    out.applied += m.contacts_applied;
    out.tunneling += m.tunneling_events;
    const World& w = sim.world();
    const std::size_t ni = w.instruments.size();
    for (const Contact& c : sim.contacts()) {
      if (c.kind != ContactKind::kInstrumentTissue || c.object_a >= ni) continue;
      const Instrument& inst = w.instruments[c.object_a].instrument;
      const TissueBody& tissue = *w.tissues[c.object_b - ni];
      const Triangle& tb = tissue.settings.triangles[c.triangle_b];
      const Triangle& ta = inst.triangles()[c.triangle_a];
      ContactTriangles tri;
      for (int k = 0; k < 3; ++k) {
        tri.a[static_cast<std::size_t>(k)] = inst.world_positions()[ta[static_cast<std::size_t>(k)]];
        tri.va[static_cast<std::size_t>(k)] = inst.velocity_at(tri.a[static_cast<std::size_t>(k)]);
        tri.b[static_cast<std::size_t>(k)] = tissue.state.positions[tb[static_cast<std::size_t>(k)]];
        tri.vb[static_cast<std::size_t>(k)] = tissue.state.velocities[tb[static_cast<std::size_t>(k)]];
      }
      if (!far_surface(inst.top_world(), tri.b)) continue;
      ++out.far_contacts;
      const Vec3 top = inst.top_world();
      const ContactResponse r = respond_contact(tri, inst.world_obb(), &top, inst.world_positions(), response);
      if (r.status == ContactStatus::kApplied) ++out.far_contacts_applied;
    }
  }).stable;
  std::printf("%s: KE max %.3g J, speed max %.3g m/s, penetration max %.3g mm, contacts %llu (applied %llu), "
              "tunneling %llu, far-surface contacts %llu (applied %llu)\n",
              file.c_str(), out.max_kinetic, out.max_speed, out.max_penetration * 1e3,
              static_cast<unsigned long long>(out.contacts), static_cast<unsigned long long>(out.applied),
              static_cast<unsigned long long>(out.tunneling), static_cast<unsigned long long>(out.far_contacts),
              static_cast<unsigned long long>(out.far_contacts_applied));
  return out;
}

/// Stable (core/stability.h: finite, kinetic energy within ½·M·(10 m/s)², as `trocar run`
/// reports it), and no vertex flung away, a stricter check of the response than stability: the
/// fastest tissue vertex stays under 10 m/s (measured with the depth-capped `obb` of every
/// shipped scene: 1.5 m/s at most, in hernia.json when the grasper stops; without the cap single
/// light vertices reached 10–45 m/s there, docs/response.md "Depth cap").
void expect_stable(const RunSummary& r) {
  EXPECT_TRUE(r.stable);
  EXPECT_LT(r.max_speed, 10.0);
}

TEST(ShippedScenes, HerniaRunsStably) {
  const RunSummary r = run_scene("hernia.json", 2.0);
  expect_stable(r);
  EXPECT_GT(r.applied, 0u);  // the grasper pushes the sac
}

TEST(ShippedScenes, ProbePressSlideRunsStably) {
  const RunSummary r = run_scene("probe_press_slide.json", 2.0);
  expect_stable(r);
  EXPECT_GT(r.applied, 0u);
}

TEST(ShippedScenes, GraspLiftRunsStably) {
  const RunSummary r = run_scene("grasp_lift.json", 2.0);
  expect_stable(r);
  EXPECT_GT(r.contacts, 0u);
}

TEST(ShippedScenes, StabRunsStablyWithNoFarSurfaceContactApplied) {
  const RunSummary r = run_scene("stab.json", 2.0);
  expect_stable(r);
  EXPECT_GT(r.applied, 0u);
  EXPECT_GT(r.far_contacts, 0u);  // the probe does reach the far surface from inside
  EXPECT_EQ(r.far_contacts_applied, 0u);
}

TEST(ShippedScenes, TappGroinScenesRunStably) {
  for (const char* file : {"tapp_indirect.json", "tapp_direct.json"}) expect_stable(run_scene(file, 2.0));
}

/// The CLI's own verdict: `trocar run SCENE --duration 2 --report FILE` says `stable: true`;
/// built_liver builds its organ from a volume (the modelling module), in a private cache.
TEST(ShippedScenes, TrocarRunReportsStable) {
  std::vector<const char*> names{"hernia", "probe_press_slide", "grasp_lift", "stab", "tapp_indirect", "tapp_direct"};
#if TROCAR_HAVE_MODELLING
  names.push_back("built_liver");
  const std::filesystem::path cache = std::filesystem::temp_directory_path() / "trocar_shipped_cache";
  ::setenv("TROCAR_CACHE_DIR", cache.c_str(), 1);
#endif
  for (const char* name : names) {
    const std::filesystem::path report =
        std::filesystem::temp_directory_path() / ("trocar_shipped_" + std::string(name) + ".json");
    const std::string cmd = std::string(TROCAR_CLI) + " run " + kScenes + "/" + name + ".json --duration 2 --report " +
                            report.string() + " --quiet > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream f(report);
    const nlohmann::json r = nlohmann::json::parse(f);
    EXPECT_TRUE(r.at("stable").get<bool>()) << name;
    EXPECT_EQ(r.at("steps").get<int>(), 2000) << name;
    std::filesystem::remove(report);
  }
}

}  // namespace
}  // namespace trocar
