// Parsing speed of each reader on real files, from memory (no disk in the loop), reported as
// bytes/s and triangles/s. Shared meshes are skipped when ../shared is absent; a generated
// icosphere written by our own writers covers OBJ and STL everywhere.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void bench_read(benchmark::State& state, const std::string& bytes, MeshFormat format) {
  std::size_t triangles = 0;
  for (auto _ : state) {
    const TriMesh mesh = read_mesh(bytes, format, "bench");
    triangles = mesh.triangle_count();
    benchmark::DoNotOptimize(mesh.positions.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["tri/s"] = benchmark::Counter(static_cast<double>(triangles),
                                               benchmark::Counter::kIsIterationInvariantRate);
}

void bench_shared(benchmark::State& state, const char* file) {
  const auto path = std::filesystem::path(TROCAR_SHARED_MESHES) / file;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("../shared/data/meshes not present");
    return;
  }
  bench_read(state, slurp(path), format_from_path(path));
}

void BM_ReadGeneratedObj(benchmark::State& state) {
  bench_read(state, write_obj(make_icosphere(0.05, 5)), MeshFormat::kObj);  // 20480 T
}
void BM_ReadGeneratedStl(benchmark::State& state) {
  bench_read(state, write_stl_binary(make_icosphere(0.05, 5)), MeshFormat::kStl);
}
BENCHMARK(BM_ReadGeneratedObj)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadGeneratedStl)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bench_shared, obj_liver_smooth, "liver_sofa_smooth.obj")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bench_shared, vrml_liver_smooth, "liver_sofa_smooth.wrl")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bench_shared, obj_stomach, "stomach_bodyparts3d_FMA7148.obj")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bench_shared, stl_abdominal_wall, "abdominal_wall_openhelp.stl")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace trocar
