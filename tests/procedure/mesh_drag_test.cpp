// The prosthetic mesh moved on the groin (docs/procedure.md, "Placing the mesh"): laid 1.2 cm too
// low on the TAPP anatomy's wall, taken at its upper edge by two graspers through their ports,
// slid 1.2 cm cranially along the wall and let go. It goes as a whole, stays where it was left,
// above the wall, and comes to rest. (Before the wall was made not graspable, the jaws took a
// bite of the wall under the mesh too, dragged it 8 mm, and on letting go the wall sprang back
// into the mesh at 5 m/s: the step blew up.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "trocar/geometry/closest_point.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

// Tips on the wall's inner surface + 1.5 mm (z = |(x, y) − (0.05, 0.02)|²/0.7, docs/anatomy.md),
// shafts toward the right and left ports; the jaws close at 0.6–0.8 s, slide to 1.6 s, open by
// 1.8 s, and the graspers withdraw 2 cm by 2.1 s.
const char* kScene = R"({"schema": 1, "name": "mesh-drag", "timestep": 0.001, "duration": 2.3,
 "gravity": [0, -1.70, 9.66],
 "anatomy": {"generate": "tapp-inguinal", "hernia": "indirect", "sac_neck_fixed": true},
 "tissues": [{"name": "mesh", "mesh": {"generate": "prosthetic-mesh", "width": 0.15, "height": 0.10, "spacing": 0.005},
   "translate": [0.0625, 0.020, 0.02], "material": {"preset": "polypropylene-mesh"}, "integrator": "xpbd",
   "lay_on": {"tissues": ["abdominal_wall", "peritoneum", "hernia_sac"], "gap": 0.0015}}],
 "tissue_contacts": [{"a": "mesh", "b": "abdominal_wall", "thickness": 0.001, "friction": 0.5, "adhesion": 20}],
 "instruments": [%INSTRUMENTS%],
 "collision": {"broad_phase": "ohc", "cell_size": "auto", "period": 0.001},
 "response": {"method": "obb", "stiffness": 500, "damping": 5, "max_force": 10}})";

/// A grasper through `port` whose tip passes through `tips` (t, x, y, z, jaw) with its shaft
/// along `turns` (rotate_deg about x and y, one per tip).
std::string grasper(const std::string& name, const std::string& port, const std::vector<std::array<Real, 5>>& tips,
                    const std::vector<std::array<Real, 2>>& turns) {
  std::string keys;
  for (std::size_t k = 0; k < tips.size(); ++k) {
    const auto& [t, x, y, z, jaw] = tips[k];
    char key[200];
    std::snprintf(key, sizeof key, R"(%s{"t": %g, "position": [%g, %g, %g], "rotate_deg": [%g, %g, 0], "jaw": %g})",
                  k ? ", " : "", t, x, y, z, turns[k][0], turns[k][1], jaw);
    keys += key;
  }
  return R"({"name": ")" + name + R"(", "port": ")" + port +
         R"(", "mesh": {"generate": "grasper", "shaft_length": 0.2}, "top_vertex": "auto",
   "jaw_triangles": [0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23],
   "motion": {"keyframes": [)" + keys + "]}}";
}

std::string drag_scene() {
  std::string text = kScene;
  const std::string instruments =
      grasper("grasper_right", "right",
              {{{0.0, 0.1, 0.064, 0.02634, 0}, {0.3, 0.1, 0.064, 0.01434, 0}, {0.6, 0.1, 0.064, 0.00784, 0},
                {0.8, 0.1, 0.064, 0.00784, 1}, {1.6, 0.1, 0.076, 0.00955, 1}, {1.8, 0.1, 0.076, 0.00955, 0},
                {2.1, 0.1, 0.076, 0.02955, 0}}},
              {{{-59.932, -51.735}, {-54.774, -40.071}, {-51.902, -35.433}, {-51.902, -35.433}, {-50.004, -41.467},
                {-50.004, -41.467}, {-50.004, -41.467}}}) +
      ",\n  " +
      grasper("grasper_left", "left",
              {{{0.0, 0.025, 0.064, 0.02366, 0}, {0.3, 0.025, 0.064, 0.01166, 0}, {0.6, 0.025, 0.064, 0.00516, 0},
                {0.8, 0.025, 0.064, 0.00516, 1}, {1.6, 0.025, 0.076, 0.00687, 1}, {1.8, 0.025, 0.076, 0.00687, 0},
                {2.1, 0.025, 0.076, 0.02687, 0}}},
              {{{-22.582, -74.502}, {-21.812, -68.021}, {-21.32, -64.732}, {-21.32, -64.732}, {-15.898, -68.916},
                {-15.898, -68.916}, {-15.898, -68.916}}});
  text.replace(text.find("%INSTRUMENTS%"), 13, instruments);
  return text;
}

std::size_t tissue_named(const World& world, const std::string& name) {
  std::size_t index = 0;
  if (!world.find_tissue(name, &index)) ADD_FAILURE() << "no tissue " << name;
  return index;
}

/// The lowest mesh vertex's height over the wall's surface (m): the nearest wall triangle by brute
/// force, signed by its normal turned into the cavity (+z).
Real lowest_over_wall(const TissueBody& mesh, const TissueBody& wall) {
  Real lowest = std::numeric_limits<Real>::infinity();
  for (const Vec3& p : mesh.state.positions) {
    Real best = std::numeric_limits<Real>::infinity(), signed_distance = 0;
    for (const Triangle& t : wall.settings.triangles) {
      const Vec3 &a = wall.state.positions[t[0]], &b = wall.state.positions[t[1]], &c = wall.state.positions[t[2]];
      const TriangleClosestPoint q = closest_point_on_triangle(p, a, b, c);
      const Real d = (p - q.point).norm();
      if (d < best) {
        Vec3 n = (b - a).cross(c - a);
        if (n.z() < 0) n = -n;
        best = d;
        signed_distance = n.dot(p - q.point) >= 0 ? d : -d;
      }
    }
    lowest = std::min(lowest, signed_distance);
  }
  return lowest;
}

TEST(MeshOnTheGroin, TwoGraspersSlideTheLaidMeshAlongTheWallAndLetItGo) {
  Scene scene = parse_scene(drag_scene(), "mesh-drag.json", ".");
  scene.settings.measure_penetration = false;
  Simulation sim = make_simulation(scene);
  const World& world = sim.world();
  const TissueBody& mesh = *world.tissues[tissue_named(world, "mesh")];
  const TissueBody& wall = *world.tissues[tissue_named(world, "abdominal_wall")];
  const std::vector<Vec3> laid = mesh.state.positions;
  const Real lowest_laid = lowest_over_wall(mesh, wall);
  Real kinetic_max = 0, kinetic_max_at = 0;
  for (int n = 0; n < 2300; ++n) {
    const StepMetrics& m = sim.step(scene.timestep);
    ASSERT_TRUE(m.finite) << "step " << n;
    if (m.kinetic_energy > kinetic_max) {
      kinetic_max = m.kinetic_energy;
      kinetic_max_at = sim.time();
    }
  }
  Real lo = 1, hi = -1, sum = 0;
  std::vector<Real> moved;
  for (std::size_t v = 0; v < laid.size(); ++v) {
    const Real dy = mesh.state.positions[v].y() - laid[v].y();
    lo = std::min(lo, dy);
    hi = std::max(hi, dy);
    sum += dy;
    moved.push_back(dy);
  }
  std::sort(moved.begin(), moved.end());
  const Real p1 = moved[moved.size() / 100], p99 = moved[moved.size() * 99 / 100];
  const Real mean = sum / static_cast<Real>(laid.size());
  const Real lowest = lowest_over_wall(mesh, wall);
  const Real kinetic_end = sim.metrics().kinetic_energy;
  std::printf("mesh left %.2f mm cranially of where it was laid (every vertex %.2f–%.2f mm, 1st–99th percentile "
              "%.2f–%.2f mm); lowest vertex %.2f mm over the wall (laid: %.2f mm); kinetic energy peak %.2g J at %.3f s, "
              "at the end %.2g J\n", 1e3 * mean, 1e3 * lo, 1e3 * hi, 1e3 * p1, 1e3 * p99, 1e3 * lowest,
              1e3 * lowest_laid, kinetic_max, kinetic_max_at, kinetic_end);
  EXPECT_GT(mean, 0.008);  // the graspers went 12 mm; the mesh followed and stays
  EXPECT_LT(mean, 0.013);
  // As a whole: nothing torn or bunched (the middle 98 % within 3 mm of one another) and no part
  // left where it was (every vertex at least 3 mm on). Solved inside the substeps, the upper
  // edge's left corner, by the left grasper's jaws, comes 3.9–7.4 mm (5 of 651 vertices; 9.0 mm
  // and more after the integrators).
  EXPECT_LT(p99 - p1, 0.003);
  EXPECT_GT(lo, 0.003);
  EXPECT_GT(lowest, 0.0005);   // never through the wall: the 1 mm contact gap, less half
  // The whole scene's kinetic energy: measured 1.8·10⁻³ J at 1.99 s (the open jaws brushing what
  // they leave as they withdraw); the blow-ups this guards against reach 1–7 J.
  EXPECT_LT(kinetic_max, 1e-2);
  EXPECT_LT(kinetic_end, 1e-6);  // at rest again
  // The wall under it was never held: the jaws hold nothing of it.
  EXPECT_FALSE(wall.graspable);
}

}  // namespace
}  // namespace trocar
