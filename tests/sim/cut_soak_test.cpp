// A seeded soak of cuts and burns on the shipped organs (docs/electrosurgery.md, "Robustness"):
// 1,000 random incisions, single triangles, whole fans and burns, each followed by simulation
// steps with the scene's instruments moving; after each, the state is finite, every surface stays
// manifold, and the detector's cached structures find what a fresh detector finds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "trocar/mesh/topology.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

std::size_t non_manifold(const MassSpringSettings& s) {
  if (s.triangles.empty()) return 0;
  TriMesh mesh;
  mesh.positions = s.rest_positions;
  mesh.triangles = s.triangles;
  const MeshTopology topology(mesh);
  return topology.nonmanifold_edges().size() + topology.nonmanifold_vertices().size();
}

std::vector<CollisionObject> objects_of(const World& world) {
  std::vector<CollisionObject> objects;
  for (const InstrumentBody& body : world.instruments)
    objects.push_back({ObjectRole::kInstrument, body.instrument.world_positions(), body.instrument.triangles()});
  for (const auto& tissue : world.tissues)
    objects.push_back({ObjectRole::kTissue, tissue->state.positions, tissue->settings.triangles});
  for (const RigidBody& rigid : world.rigids) objects.push_back({ObjectRole::kRigid, rigid.mesh.positions, rigid.mesh.triangles});
  return objects;
}

/// Triangles around a random walk of `length` steps across edges from triangle `start`.
std::vector<std::uint32_t> walk(const MassSpringSettings& s, std::uint32_t start, int length, std::mt19937& rng) {
  std::vector<std::uint32_t> out{start};
  std::uint32_t at = start;
  for (int k = 0; k < length; ++k) {
    const Triangle& t = s.triangles[at];
    std::vector<std::uint32_t> next;
    for (std::uint32_t u = 0; u < s.triangles.size(); ++u) {
      if (u == at) continue;
      int shared = 0;
      for (std::uint32_t a : s.triangles[u])
        for (std::uint32_t b : t) shared += a == b ? 1 : 0;
      if (shared == 2) next.push_back(u);
    }
    if (next.empty()) break;
    at = next[rng() % next.size()];
    out.push_back(at);
  }
  return out;
}

void soak(const char* scene_name, int operations, std::uint32_t seed) {
  Scene scene = load_scene(std::filesystem::path(TROCAR_TEST_SCENES) / scene_name);
  scene.settings.measure_penetration = true;
  Simulation sim(std::move(scene.world), scene.settings);
  std::mt19937 rng(seed);
  const std::size_t nt = sim.world().tissues.size();
  std::vector<std::size_t> was_non_manifold(nt);
  for (std::size_t t = 0; t < nt; ++t) was_non_manifold[t] = non_manifold(sim.world().tissues[t]->settings);
  int cuts = 0, burns = 0, emptied = 0;
  for (int op = 0; op < operations; ++op) {
    const std::size_t t = rng() % nt;
    const MassSpringSettings& s = sim.world().tissues[t]->settings;
    if (s.triangles.empty()) {
      ++emptied;
      continue;
    }
    const auto k = static_cast<std::uint32_t>(rng() % s.triangles.size());
    const int kind = static_cast<int>(rng() % 10);
    if (kind < 4) {
      sim.cut(t, walk(s, k, 1 + static_cast<int>(rng() % 8), rng));  // an incision
      ++cuts;
    } else if (kind < 6) {
      const std::uint32_t one[] = {k};
      sim.cut(t, one);
      ++cuts;
    } else if (kind < 7) {
      // A vertex's whole fan: what is around it may fall apart.
      const std::uint32_t v = s.triangles[k][rng() % 3];
      std::vector<std::uint32_t> fan;
      for (std::uint32_t u = 0; u < s.triangles.size(); ++u)
        if (std::find(s.triangles[u].begin(), s.triangles[u].end(), v) != s.triangles[u].end()) fan.push_back(u);
      sim.cut(t, fan);
      ++cuts;
    } else {
      // A burn: enough heat to coagulate, sometimes to boil off (cut by the next steps).
      for (std::uint32_t u : walk(s, k, static_cast<int>(rng() % 4), rng))
        sim.heat(t, u, std::uniform_real_distribution<Real>(0.01, 2.0)(rng));
      ++burns;
    }
    for (int n = 0; n < 3; ++n) {
      const StepMetrics& m = sim.step(scene.timestep);
      ASSERT_TRUE(m.finite) << scene_name << " op " << op << " step " << n;
      ASSERT_LT(m.tissue_rms_speed, 10.0) << scene_name << " op " << op;
    }
    for (std::size_t u = 0; u < nt; ++u) {
      const MassSpringSettings& now = sim.world().tissues[u]->settings;
      ASSERT_LE(non_manifold(now), was_non_manifold[u]) << scene_name << " op " << op << " tissue " << u;
      for (const Triangle& tri : now.triangles)
        for (std::uint32_t v : tri) ASSERT_LT(v, now.vertex_count());
      ASSERT_EQ(sim.world().tissues[u]->state.positions.size(), now.vertex_count());
      ASSERT_EQ(sim.thermal(u).size(), now.triangles.size());
    }
    if (op % 50 == 49 || op == operations - 1) {
      // The detector's caches (clusters kept per object) against a fresh detector.
      const std::vector<CollisionObject> objects = objects_of(sim.world());
      OhcSettings ohc;
      ohc.cell_size = scene.settings.cell_size;
      CollisionDetector fresh(ohc);
      fresh.set_instrument_pairs_only(true);
      std::vector<Contact> expected, found;
      fresh.detect(objects, expected);
      sim.detector().detect(objects, found);
      ASSERT_EQ(found.size(), expected.size()) << scene_name << " op " << op;
      for (std::size_t c = 0; c < found.size(); ++c) {
        ASSERT_EQ(found[c].object_a, expected[c].object_a);
        ASSERT_EQ(found[c].triangle_a, expected[c].triangle_a);
        ASSERT_EQ(found[c].object_b, expected[c].object_b);
        ASSERT_EQ(found[c].triangle_b, expected[c].triangle_b);
      }
    }
  }
  Real cut_area = 0;
  for (std::size_t t = 0; t < nt; ++t) cut_area += sim.burn_tally(t).cut_area;
  std::printf("%s: %d cuts, %d burns (%d ops on emptied tissues), %.0f mm² cut\n", scene_name, cuts, burns, emptied,
              1e6 * cut_area);
}

TEST(CutSoak, ThousandCutsAndBurnsOnTheShippedOrgansStayFiniteManifoldAndDetected) {
  soak("probe_press_slide.json", 300, 1);  // the liver lobe (closed) under a moving probe
  soak("hernia.json", 300, 2);             // the hernia peritoneum (open, with its sac) and the wall
  soak("tapp_indirect.json", 400, 3);      // the TAPP groin: wall, vessels, vas, sac, peritoneum
}

}  // namespace
}  // namespace trocar
