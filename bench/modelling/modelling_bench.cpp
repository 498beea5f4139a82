// A 256³ label map (1 mm voxels) of a rotated ellipsoid organ, 220 × 160 × 120 mm, built to a
// 6,000-triangle textured organ on one core (VTK runs sequentially: modelling/vtk_threads.h):
// the whole pipeline as `trocar mesh build` runs it less the file writing, and its stages
// as counters (seconds, median of the repetitions with --benchmark_repetitions). Target: under
// one second in all. BM_BuildOrganFullResolution forces the extraction stride to 1 (the
// lever the default takes when the surface would far exceed the budget), BM_Decimate* time
// the decimation alone on the two extraction grids.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include "trocar/modelling/decimate.h"
#include "trocar/modelling/organ_builder.h"
#include "trocar/modelling/phantoms.h"

namespace trocar {
namespace {

const Volume& label_256() {
  static const Volume v = [] {
    const Vec3 semi(0.110, 0.080, 0.060);
    const Mat3 rot = Eigen::AngleAxis<Real>(0.4, Vec3(1, 1, 0).normalized()).toRotationMatrix();
    const Vec3 origin = Vec3::Constant(-127.5e-3);
    return rasterise({256, 256, 256}, 1e-3, origin, [&](const Vec3& x) {
      return (rot.transpose() * x).cwiseQuotient(semi).squaredNorm() <= 1 ? 5 : 0;
    });
  }();
  return v;
}

void run_build(benchmark::State& state, int stride) {
  const Volume& v = label_256();
  OrganBuildOptions o;
  o.query.label = "5";
  o.measure_distance = false;
  o.surface.extract_stride = stride;
  OrganBuild b;
  for (auto _ : state) {
    b = build_organ(v, o);
    benchmark::DoNotOptimize(b.mesh.positions.data());
  }
  const SurfaceTimes& t = b.surface.times;
  state.counters["components_s"] = t.components;
  state.counters["extract_s"] = t.extract;
  state.counters["smooth_s"] = t.smooth;
  state.counters["decimate_s"] = t.decimate;
  state.counters["checks_s"] = b.seconds_quality;
  state.counters["uv_texture_s"] = b.seconds_uv + b.seconds_texture;
  state.counters["triangles"] = static_cast<double>(b.mesh.triangle_count());
  state.counters["stride"] = b.surface.stride;
  state.counters["volume_error_pct"] = 100 * (b.mesh_volume / b.voxel_volume - 1);
  // Accuracy, outside the timing: the same build measured against the full-resolution surface.
  o.measure_distance = true;
  const OrganBuild measured = build_organ(v, o);
  state.counters["hausdorff_voxels"] = measured.distance.max / v.spacing.minCoeff();
  state.counters["mean_distance_voxels"] = measured.distance.mean / v.spacing.minCoeff();
}

void BM_BuildOrgan256(benchmark::State& state) { run_build(state, 0); }
void BM_BuildOrganFullResolution(benchmark::State& state) { run_build(state, 1); }
BENCHMARK(BM_BuildOrgan256)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_BuildOrganFullResolution)->Unit(benchmark::kMillisecond)->Iterations(1);
void BM_BuildOrganStride3(benchmark::State& state) { run_build(state, 3); }
BENCHMARK(BM_BuildOrganStride3)->Unit(benchmark::kMillisecond)->Iterations(3);

/// Decimation alone, from the smoothed surface of each grid.
void run_decimate(benchmark::State& state, int stride) {
  OrganBuildOptions o;
  o.query.label = "5";
  o.measure_distance = false;
  o.texture_chart_pixels = 0;
  o.surface.extract_stride = stride;
  o.surface.target_triangles = 0;  // keep the smoothed surface
  const TriMesh smoothed = build_organ(label_256(), o).mesh;
  for (auto _ : state) {
    const TriMesh m = decimate_preserving_topology(smoothed, 6000);
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.counters["input_triangles"] = static_cast<double>(smoothed.triangle_count());
}

void BM_DecimateStride2(benchmark::State& state) { run_decimate(state, 2); }
void BM_DecimateFullResolution(benchmark::State& state) { run_decimate(state, 1); }
BENCHMARK(BM_DecimateStride2)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_DecimateFullResolution)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace trocar
