// Frame times of the three broad phases (+ narrow phase) on the thesis-sized scene and larger
// ones. A measuring tool, not a test: it is built as build/tests/collision/collision_timing and
// not registered with ctest (targets are checked by benchmarks, never by timed tests).
// The benchmark binary in bench/collision compares against FCL and Bullet.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "../scene_util.h"
#include "trocar/core/timer.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

struct Timing {
  double median_us = 0;
  double p95_us = 0;
  double broad_median_us = 0;
  std::size_t pairs = 0;
  std::size_t candidates = 0;
};

Timing time_frames(test::CuttingScene& cut, BroadPhaseKind kind, int frames) {
  CollisionDetector detector(kind);
  std::vector<double> total;
  std::vector<double> broad;
  Timing t;
  for (int f = -3; f < frames; ++f) {  // 3 warm-up frames
    cut.set_frame(std::max(f, 0) % 50);
    const auto objects = cut.scene.objects();
    Timer timer;
    const auto found = detector.detect(objects);
    const double us = timer.microseconds();
    if (f < 0) continue;
    total.push_back(us);
    broad.push_back(detector.timings().broad_phase_us);
    t.pairs = std::max(t.pairs, found.size());
    t.candidates = std::max<std::size_t>(t.candidates, detector.candidates().size());
  }
  std::sort(total.begin(), total.end());
  std::sort(broad.begin(), broad.end());
  t.median_us = total[total.size() / 2];
  t.p95_us = total[total.size() * 95 / 100];
  t.broad_median_us = broad[broad.size() / 2];
  return t;
}

void report(const char* scene, test::CuttingScene& cut, int frames, bool with_brute) {
  for (const BroadPhaseKind kind : {BroadPhaseKind::kOhc, BroadPhaseKind::kBvh, BroadPhaseKind::kBruteForce}) {
    if (kind == BroadPhaseKind::kBruteForce && !with_brute) continue;
    const int n = kind == BroadPhaseKind::kBruteForce ? 3 : frames;
    const Timing t = time_frames(cut, kind, n);
    std::printf("%-34s %-6s tissue %7zu tri, tool %5zu tri: median %10.1f us  p95 %10.1f us  broad %10.1f us  "
                "candidates %6zu  pairs(max) %4zu\n",
                scene, broad_phase_name(kind), cut.tissue_rest.triangle_count(), cut.tool_rest.triangle_count(),
                t.median_us, t.p95_us, t.broad_median_us, t.candidates, t.pairs);
  }
}

TEST(CollisionTiming, ThesisScene) {
  // 6,962-triangle bulged sheet (59×59 cells, 10 cm, 2 cm bulge) against the 952-triangle
  // grasper jaw (mm → m), or a 4.5 mm radius capsule when the shared meshes are absent.
  auto jaw = test::shared_mesh("grasper_jaw_maryland_left_lapgym.stl", 0.001);
  TriMesh tool = jaw ? std::move(*jaw) : make_capsule(0.0045, 0.02, 24, 10);
  test::CuttingScene cut(make_sheet(0.1, 0.1, 59, 59, 0.02), tool, 0.0012, 0.0005, 0.0005);
  report("sheet 59x59 vs jaw", cut, 2000, true);
  test::CuttingScene sphere(make_icosphere(0.05, 4), tool, 0.0012, 0.0005, 0.0005);
  report("icosphere L4 vs jaw", sphere, 2000, false);
  auto gall = test::shared_mesh("gallbladder_lapgym.stl", 0.001);
  if (gall) {
    test::CuttingScene g(std::move(*gall), tool, 0.0015, 0.0005, 0.0005);
    report("gallbladder 14.7K vs jaw", g, 1000, false);
  }
  auto wall = test::shared_mesh("abdominal_wall_openhelp.stl", 0.001);
  if (wall) {
    test::CuttingScene w(std::move(*wall), tool, 0.0015, 0.0005, 0.0005);
    report("abdominal wall 32K vs jaw", w, 500, false);
  }
  test::CuttingScene big(make_sheet(0.3, 0.3, 592, 592, 0.06), tool, 0.0012, 0.0002, 0.0002);
  report("sheet 592x592 (700K) vs jaw", big, 60, false);
}

}  // namespace
}  // namespace trocar
