// Tissue-against-tissue pass (docs/response.md, "Tissue against tissue"): one step of the
// TissueContactSolver (begin_step + solve: grid, candidates, 4 Gauss–Seidel sweeps, velocities)
// for the 15 × 10 cm prosthetic mesh at 5 mm (651 V) resting on a 20 × 16 cm wall sheet (546 V),
// mesh–wall and mesh self contact, after 300 settling steps with the integrators. The integrators
// are not timed.
// BM_XpbdMeshOnWallStep times the whole step of the XPBD pair both ways (below).
// Run: bench_response --benchmark_filter=TissueContact --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <memory>

#include "trocar/mesh/generate.h"
#include "trocar/mesh/prosthetic_mesh.h"
#include "trocar/response/tissue_contact.h"
#include "trocar/response/xpbd_coupling.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/material.h"

namespace trocar {
namespace {

/// The wall sheet (corners fixed) and the mesh 3 mm over it, each with its state, integrator of
/// `kind` and loads.
struct MeshOnWall {
  MassSpringSettings wall, mesh;
  MassSpringState ws, ms;
  MassSpringIntegrator wi, mi;
  TissueLoads wl, ml;
  static MassSpringSettings wall_model() {
    FixedSelection border;
    border.indices = {0, 25, 520, 545};  // the corners of the 26 × 21 grid
    MassSpringMaterial wm = material_preset("peritoneum");
    wm.k_home = 20;
    return MassSpringSettings::build(make_sheet(0.2, 0.16, 25, 20), wm, border, Vec3(0, 0, -9.81));
  }
  static MassSpringSettings mesh_model() {
    TriMesh sheet = make_prosthetic_mesh(0.15, 0.10, 0.005);
    for (Vec3& p : sheet.positions) p.z() += 0.003;
    return MassSpringSettings::build(sheet, material_preset("polypropylene-mesh"), {}, Vec3(0, 0, -9.81));
  }
  explicit MeshOnWall(IntegratorKind kind)
      : wall(wall_model()), mesh(mesh_model()), ws(MassSpringState::at_rest(wall)), ms(MassSpringState::at_rest(mesh)),
        wi(wall, kind), mi(mesh, kind) {
    wl.reset(wall.vertex_count());
    ml.reset(mesh.vertex_count());
  }
};

void BM_TissueContactMeshOnWall(benchmark::State& state) {
  MeshOnWall scene(IntegratorKind::kImplicitEuler);
  auto& [wall, mesh, ws, ms, wi, mi, wl, ml] = scene;
  TissueContactSolver solver({{&wall, &ws}, {&mesh, &ms}}, {{1, 0, 1e-3, 0.3}, {1, 1, 1e-3, 0.3}});
  constexpr Real dt = 1e-3;
  Real t = 0;
  for (int n = 0; n < 300; ++n) {
    solver.begin_step();
    wi.step(ws, wl, dt);
    mi.step(ms, ml, dt);
    solver.solve(dt, t += dt);
  }
  const MassSpringState ws0 = ws, ms0 = ms;
  for (auto _ : state) {
    state.PauseTiming();
    ws = ws0;  // the same settled state every time, one step of the integrators applied
    ms = ms0;
    solver.begin_step();
    wi.step(ws, wl, dt);
    mi.step(ms, ml, dt);
    state.ResumeTiming();
    solver.solve(dt, t);
    benchmark::DoNotOptimize(ms.positions.data());
  }
  state.counters["corrected"] = solver.corrected();
}
BENCHMARK(BM_TissueContactMeshOnWall)->Unit(benchmark::kMicrosecond);

// The same scene with both tissues XPBD (4 substeps), the whole step timed: the contacts solved
// inside the substeps with the tissues in lock-step (step_coupled; arg 1) against the two
// integrators followed by the pass after them (arg 0). Both from the same settled state.
void BM_XpbdMeshOnWallStep(benchmark::State& state) {
  const bool coupled = state.range(0) != 0;
  MeshOnWall scene(IntegratorKind::kXpbd);
  auto& [wall, mesh, ws, ms, wi, mi, wl, ml] = scene;
  TissueContactSolver solver({{&wall, &ws}, {&mesh, &ms}}, {{1, 0, 1e-3, 0.3}});
  const CoupledTissue tissues[] = {{wi.xpbd(), &ws, &wl, nullptr}, {mi.xpbd(), &ms, &ml, nullptr}};
  XpbdStats stats[2];
  constexpr Real dt = 1e-3;
  Real t = 0;
  const auto step = [&] {
    solver.begin_step();
    if (coupled) {
      step_coupled(tissues, solver, dt, 4, t += dt, stats);
    } else {
      wi.step(ws, wl, dt);
      mi.step(ms, ml, dt);
      solver.solve(dt, t += dt);
    }
  };
  for (int n = 0; n < 300; ++n) step();
  for (auto _ : state) {
    step();
    benchmark::DoNotOptimize(ms.positions.data());
  }
  state.counters["corrected"] = solver.corrected();
}
BENCHMARK(BM_XpbdMeshOnWallStep)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace trocar
