// remove_triangles (tissue/cut.h): the cost of one electrosurgical cut, three triangles opened in
// a flat 71 × 71-cell sheet (10 082 triangles, 5 184 vertices, density-lumped masses, structural
// and bending springs), timed from the built model to the cut model (the input is not changed, so
// every iteration does the same cut). The three triangles are in cells (20, 20), (35, 35) and
// (50, 50), far apart, so no vertex is split. For scale, the CutReferenceBuild row times
// MassSpringSettings::build on the same mesh (what rebuilding from the material would cost) and
// CutReferenceCopy a plain copy of the model (the floor for any function that returns a new
// model: most of it is the kernel mapping fresh pages for the ~1.5 MB of arrays).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/tissue/cut.h"
#include "trocar/tissue/material.h"
#include "trocar/tissue/settings.h"

namespace trocar {
namespace {

constexpr std::size_t kCells = 71;

const TriMesh& sheet() {
  static const TriMesh mesh = make_sheet(0.2, 0.2, kCells, kCells);
  return mesh;
}

MassSpringMaterial sheet_material() {
  MassSpringMaterial m;
  m.mass = 0;
  m.density = 1060;
  m.sheet_thickness = 0.002;
  return m;
}

const MassSpringSettings& sheet_settings() {
  static const MassSpringSettings s = MassSpringSettings::build(sheet(), sheet_material());
  return s;
}

void BM_CutRemove3(benchmark::State& state) {
  const MassSpringSettings& s = sheet_settings();
  const std::vector<std::uint32_t> removed = {
      static_cast<std::uint32_t>(2 * (20 * kCells + 20)),
      static_cast<std::uint32_t>(2 * (35 * kCells + 35)),
      static_cast<std::uint32_t>(2 * (50 * kCells + 50)),
  };
  std::size_t triangles = 0, springs = 0;
  for (auto _ : state) {
    const CutTopology cut = remove_triangles(s, removed);
    triangles = cut.settings.triangles.size();
    springs = cut.settings.springs.size();
    benchmark::DoNotOptimize(cut.settings.springs.data());
  }
  state.counters["triangles_before"] = static_cast<double>(s.triangles.size());
  state.counters["triangles_after"] = static_cast<double>(triangles);
  state.counters["springs_after"] = static_cast<double>(springs);
  state.counters["vertices"] = static_cast<double>(s.vertex_count());
}
BENCHMARK(BM_CutRemove3)->Name("CutRemove3/sheet10k")->Unit(benchmark::kMicrosecond);

void BM_CutReferenceBuild(benchmark::State& state) {
  const TriMesh& mesh = sheet();
  const MassSpringMaterial material = sheet_material();
  for (auto _ : state) {
    const MassSpringSettings s = MassSpringSettings::build(mesh, material);
    benchmark::DoNotOptimize(s.springs.data());
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
}
BENCHMARK(BM_CutReferenceBuild)->Name("CutReferenceBuild/sheet10k")->Unit(benchmark::kMicrosecond);

void BM_CutReferenceCopy(benchmark::State& state) {
  const MassSpringSettings& s = sheet_settings();
  for (auto _ : state) {
    const MassSpringSettings copy = s;
    benchmark::DoNotOptimize(copy.springs.data());
  }
}
BENCHMARK(BM_CutReferenceCopy)->Name("CutReferenceCopy/sheet10k")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace trocar
