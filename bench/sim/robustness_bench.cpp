// Simulation::step of the robustness suite (docs/robustness.md) with metrics off, as the
// real-time runtime runs it: each generated organ under the hook probe held pressed (the press
// motion, timed after it ends), for the default sdf response and the seed's obb. Targets: step
// median ≤ 1 ms up to 12K triangles, ≤ 2.5 ms at 25K; implicit deformation ≤ 150 ns/vertex.
#include <benchmark/benchmark.h>

#include <vector>

#include "trocar/study/robustness.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

const std::vector<SuiteOrgan>& organs() {
  static const std::vector<SuiteOrgan> family = generated_organs(1);
  return family;
}

/// arg 0: organ index in the generated family; arg 1: 0 = sdf, 1 = obb.
void BM_SuitePressHeld(benchmark::State& state) {
  const SuiteOrgan& organ = organs()[static_cast<std::size_t>(state.range(0))];
  const ResponseMethod method = state.range(1) == 0 ? ResponseMethod::kSdf : ResponseMethod::kObb;
  Real duration = 0;
  World world = suite_world(organ, SuiteMotion::kPress, duration);
  SimulationSettings settings = suite_settings(method);
  settings.measure_penetration = false;
  Simulation sim(std::move(world), settings);
  drive(sim, 1e-3, static_cast<std::size_t>(duration / 1e-3));
  double deformation = 0, cg = 0, contacts = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    const StepMetrics& m = sim.step(1e-3);
    deformation += m.timings.deformation;
    cg += m.cg_iterations;
    contacts += m.contacts;
    ++steps;
  }
  const double n = static_cast<double>(std::max<std::int64_t>(steps, 1));
  state.counters["deform_ns_per_vertex"] = deformation * 1e3 / n / static_cast<double>(organ.mesh.vertex_count());
  state.counters["cg_per_step"] = cg / n;
  state.counters["contacts"] = contacts / n;
  state.counters["triangles"] = static_cast<double>(organ.mesh.triangle_count());
  state.SetLabel(organ.name + " " + response_method_name(method));
}
BENCHMARK(BM_SuitePressHeld)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.5);

}  // namespace
}  // namespace trocar
