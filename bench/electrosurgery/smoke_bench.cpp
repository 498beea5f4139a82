// Surgical smoke (src/trocar/electrosurgery/smoke.h): one step of a full field, emission into a
// full field (the faintest make room), and one line of sight through it.
//
// Scenario: the default settings (capacity 4096); a hook cutting at 30 W of vaporisation
// (0.03 J a millisecond, 3 particles) stepped at 1 ms until the pool is full, then 0.5 s more, so
// the field is a plume of mixed ages, all live. BM_SmokeStep times step(1 ms); the field is put
// back to that state every 256 steps outside the timing (no particle dies in 256 ms, so every
// timed step moves all 4096). Counters: particles, ns_per_particle.
// Run: bench_electrosurgery --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "trocar/electrosurgery/smoke.h"

namespace trocar {
namespace {

SmokeField full_field() {
  SmokeField field(SmokeSettings{}, 1);
  while (field.size() < field.capacity()) {
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.03);
    field.step(1e-3);
  }
  for (int k = 0; k < 500; ++k) {
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.03);
    field.step(1e-3);
  }
  return field;
}

void BM_SmokeStep(benchmark::State& state) {
  const SmokeField start = full_field();
  SmokeField field = start;
  int steps = 0;
  for (auto _ : state) {
    if (++steps == 256) {
      state.PauseTiming();
      field = start;  // same sizes: copies, no allocation
      steps = 0;
      state.ResumeTiming();
    }
    field.step(1e-3);
    benchmark::DoNotOptimize(field.particles().data());
    benchmark::ClobberMemory();
  }
  const auto n = static_cast<double>(field.size());
  state.counters["particles"] = n;
  state.counters["ns_per_particle"] =
      benchmark::Counter(n * static_cast<double>(state.iterations()) * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SmokeStep)->Unit(benchmark::kMicrosecond);

// One millisecond of a 30 W cut (3 particles) into the full pool: the choice of the 3 faintest
// and the compaction, O(capacity).
void BM_SmokeEmitIntoFull(benchmark::State& state) {
  SmokeField field = full_field();
  for (auto _ : state) {
    field.emit(Vec3::Zero(), Vec3::UnitZ(), 0.03);
    benchmark::DoNotOptimize(field.particles().data());
    benchmark::ClobberMemory();
  }
  state.counters["particles"] = static_cast<double>(field.size());
}
BENCHMARK(BM_SmokeEmitIntoFull)->Unit(benchmark::kMicrosecond);

// The scope's line of sight across the plume (optical_depth over all 4096 particles).
void BM_SmokeOpticalDepth(benchmark::State& state) {
  const SmokeField field = full_field();
  for (auto _ : state) {
    benchmark::DoNotOptimize(field.optical_depth(Vec3(-0.08, 0, 0.02), Vec3(0.08, 0, 0.02)));
  }
  state.counters["particles"] = static_cast<double>(field.size());
}
BENCHMARK(BM_SmokeOpticalDepth)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace trocar
