// The electrosurgery work inside the step (docs/electrosurgery.md): the thermal field's step on a
// burning peritoneum, and an electrode's touch test against it.
//
// Scenario: the shipped incision scene's sheet, 14 × 8 cm in 2 mm cells (5600 triangles); the hook's
// electrode (its points every 0.25 mm along the edges of its 6 mm tip, as the Simulation samples
// it) lying on the sheet's middle. BM_ThermalStep: one 1 ms step with 40 W shared over the
// touched triangles (the field hot: the whole sheet's loop runs). BM_TouchTriangles: which triangles
// the electrode touches. BM_ThermalIdle: the step of a field nothing heats (the cost of a
// tissue when no electrode burns: a scan of the power).
// Run: bench_electrosurgery --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "trocar/electrosurgery/electrode.h"
#include "trocar/electrosurgery/thermal.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/instruments.h"

namespace trocar {
namespace {

struct Burning {
  TriMesh sheet = make_sheet(0.14, 0.08, 70, 40);
  std::vector<Real> areas;
  std::vector<Vec3> points;
  std::vector<std::uint8_t> touched;
  std::vector<Real> power;
  Burning() {
    for (const Triangle& t : sheet.triangles)
      areas.push_back(0.5 * (sheet.positions[t[1]] - sheet.positions[t[0]])
                                .cross(sheet.positions[t[2]] - sheet.positions[t[0]])
                                .norm());
    const InstrumentMesh hook = make_hook_probe();
    const Quat q(Eigen::AngleAxis<Real>(std::numbers::pi / 2, Vec3::UnitZ()));
    for (const Vec3& p : electrode_points(hook.mesh.positions, hook.mesh.triangles, Vec3::UnitZ(), 0.006, 0.00025))
      points.push_back(q * p + Vec3(0.001, 0.0005, -0.0002));
    touched.assign(sheet.triangles.size(), 0);
    power.assign(sheet.triangles.size(), 0.0);
    const Real area = touch_triangles(points, sheet.positions, sheet.triangles, areas, 0.0005, touched);
    share_power(40, area, touched, areas, power);
  }
};

void BM_TouchTriangles(benchmark::State& state) {
  Burning b;
  for (auto _ : state) {
    const Real area = touch_triangles(b.points, b.sheet.positions, b.sheet.triangles, b.areas, 0.0005, b.touched);
    benchmark::DoNotOptimize(area);
  }
  state.counters["points"] = static_cast<double>(b.points.size());
  state.counters["triangles"] = static_cast<double>(b.sheet.triangles.size());
}
BENCHMARK(BM_TouchTriangles)->Unit(benchmark::kMicrosecond);

void BM_ThermalStep(benchmark::State& state) {
  Burning b;
  ThermalField field(ThermalProperties{}, b.sheet.triangles, b.sheet.positions, b.areas);
  for (auto _ : state) field.step(b.power, 1e-3);
  state.counters["triangles"] = static_cast<double>(field.size());
}
BENCHMARK(BM_ThermalStep)->Unit(benchmark::kMicrosecond);

void BM_ThermalIdle(benchmark::State& state) {
  Burning b;
  ThermalField field(ThermalProperties{}, b.sheet.triangles, b.sheet.positions, b.areas);
  const std::vector<Real> none(b.power.size(), 0.0);
  for (auto _ : state) field.step(none, 1e-3);
}
BENCHMARK(BM_ThermalIdle)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace trocar
