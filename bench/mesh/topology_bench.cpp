// Topology build, validate and repair (with vertex merge) on a ~20k-triangle icosphere and on
// the shared OpenHELP abdominal wall (31934 T; skipped when TROCAR_SHARED_MESHES is absent).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <optional>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/repair.h"
#include "trocar/mesh/topology.h"
#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

const TriMesh& icosphere() {
  static const TriMesh mesh = make_icosphere(0.05, 5);  // 10242 V, 20480 T
  return mesh;
}

/// The abdominal wall, loaded once; nullopt when the file or its reader is not there.
const std::optional<TriMesh>& abdominal_wall() {
  static const std::optional<TriMesh> mesh = []() -> std::optional<TriMesh> {
    const auto path = std::filesystem::path(TROCAR_SHARED_MESHES) / "abdominal_wall_openhelp.stl";
    if (!std::filesystem::exists(path)) return std::nullopt;
    try {
      return load_mesh(path);
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }();
  return mesh;
}

/// The icosphere as a triangle soup (3 vertices per triangle), for the merge benchmarks.
const TriMesh& icosphere_soup() {
  static const TriMesh mesh = [] {
    TriMesh soup;
    for (std::size_t t = 0; t < icosphere().triangles.size(); ++t) {
      const auto base = static_cast<std::uint32_t>(soup.positions.size());
      for (const Vec3& p : icosphere().corners(t)) soup.positions.push_back(p);
      soup.triangles.push_back({base, base + 1, base + 2});
    }
    return soup;
  }();
  return mesh;
}

void set_counters(benchmark::State& state, const TriMesh& mesh) {
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(mesh.triangles.size()));
}

template <typename F>
void run_on(benchmark::State& state, const TriMesh* mesh, F&& body) {
  if (mesh == nullptr) {
    state.SkipWithError("shared mesh not available");
    return;
  }
  for (auto _ : state) body(*mesh);
  set_counters(state, *mesh);
}

const TriMesh* wall() { return abdominal_wall() ? &*abdominal_wall() : nullptr; }

void BM_TopologyIcosphere(benchmark::State& state) {
  run_on(state, &icosphere(), [](const TriMesh& m) { benchmark::DoNotOptimize(MeshTopology(m)); });
}
void BM_TopologyAbdominalWall(benchmark::State& state) {
  run_on(state, wall(), [](const TriMesh& m) { benchmark::DoNotOptimize(MeshTopology(m)); });
}
void BM_ValidateIcosphere(benchmark::State& state) {
  run_on(state, &icosphere(), [](const TriMesh& m) { benchmark::DoNotOptimize(validate(m)); });
}
void BM_ValidateAbdominalWall(benchmark::State& state) {
  run_on(state, wall(), [](const TriMesh& m) { benchmark::DoNotOptimize(validate(m)); });
}
/// Full repair (exact merge + every default step) on a copy of the mesh; the copy is timed too.
void BM_RepairExactMergeAbdominalWall(benchmark::State& state) {
  run_on(state, wall(), [](const TriMesh& m) {
    TriMesh copy = m;
    benchmark::DoNotOptimize(repair(copy));
  });
}
void BM_RepairToleranceMergeAbdominalWall(benchmark::State& state) {
  run_on(state, wall(), [](const TriMesh& m) {
    TriMesh copy = m;
    RepairOptions opts;
    opts.merge_tolerance_rel = 1e-9;
    benchmark::DoNotOptimize(repair(copy, opts));
  });
}
/// Welding a 61440-vertex soup back into the 10242-vertex sphere.
void BM_RepairExactMergeIcosphereSoup(benchmark::State& state) {
  run_on(state, &icosphere_soup(), [](const TriMesh& m) {
    TriMesh copy = m;
    benchmark::DoNotOptimize(repair(copy));
  });
}
void BM_RepairToleranceMergeIcosphereSoup(benchmark::State& state) {
  run_on(state, &icosphere_soup(), [](const TriMesh& m) {
    TriMesh copy = m;
    RepairOptions opts;
    opts.merge_tolerance_rel = 1e-9;
    benchmark::DoNotOptimize(repair(copy, opts));
  });
}

BENCHMARK(BM_TopologyIcosphere)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TopologyAbdominalWall)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ValidateIcosphere)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ValidateAbdominalWall)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RepairExactMergeAbdominalWall)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RepairToleranceMergeAbdominalWall)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RepairExactMergeIcosphereSoup)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RepairToleranceMergeIcosphereSoup)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace trocar
