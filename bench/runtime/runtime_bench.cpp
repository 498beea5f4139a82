// The haptic loop's timing while physics runs beside it on the other core (multirate, metrics
// off, as `trocar run --realtime`): achieved tick rate, p99 period and jitter, deadline-miss
// fraction, the tick's own compute, and the physics rate achieved. Scenes: the probe–liver press
// (shared meshes; skipped without them), the shipped press scene held in contact, and the
// generated 11.5K-triangle organ (flat-12k-s1) on the xpbd integrator with the hook held 8 mm
// in. Each run is 3 s of wall-clock time after a 0.5 s warm-up press. BM_BareLoop is this
// machine's floor: the same wait and the same lateness rule (a tick more than 0.1 period late, or
// a slot skipped) with nothing to compute and no physics beside it, run in the same binary.
// Targets: the haptic on-time fraction within 0.5 percentage points of the bare loop's; physics
// ≥ 950 Hz on the 11.5K organ in contact.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "sim/probe_liver_scene.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/organ_shapes.h"
#include "trocar/runtime/realtime.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

/// The shipped press scene with its probe pressed 2.25 cm into the lobe within 0.5 s and held.
std::string held_press_text() {
  std::ifstream in(TROCAR_BENCH_SCENES "/probe_press_slide.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["response"]["method"] = "sdf";
  scene["instruments"][0]["motion"] = {{"keyframes",
                                        {{{"t", 0.0}, {"position", {0, 0, 0.045}}},
                                         {{"t", 0.5}, {"position", {0, 0, 0.0225}}}}}};
  return scene.dump();
}

/// The generated flat-12k-s1 organ (11,520 triangles, metres, centred) written to a temporary OBJ,
/// on xpbd with a medium material (0.3 kg, k 100 N/m, area and volume on), the hook pressed 8 mm
/// into its top within 0.5 s and held.
std::string xpbd_organ_text() {
  TriMesh mesh;
  for (const OrganShapeSpec& spec : organ_family(1))
    if (spec.name == "flat-12k-s1") mesh = make_organ_shape(spec);
  const Vec3 centre = Aabb::of_points(mesh.positions).center();
  for (Vec3& x : mesh.positions) x -= centre;
  const Aabb box = Aabb::of_points(mesh.positions);
  Vec3 top = mesh.positions[0];
  for (const Vec3& x : mesh.positions)
    if (x.z() > top.z()) top = x;
  const std::string file = (std::filesystem::temp_directory_path() / "trocar_bench_flat12k.obj").string();
  save_mesh(mesh, file);
  nlohmann::json tissue;
  tissue["name"] = "organ";
  tissue["mesh"] = file;
  tissue["material"] = {{"mass", 0.3},   {"k_structural", 100}, {"k_bending", 10},
                        {"k_area", 10},  {"k_volume", 100},     {"k_home", 4.5}};
  tissue["fixed"]["below_plane"]["point"] = {0, 0, box.min.z() + 0.2 * box.size().z()};
  tissue["fixed"]["below_plane"]["normal"] = {0, 0, 1};
  tissue["integrator"] = "xpbd";
  nlohmann::json hook;
  hook["name"] = "hook";
  hook["mesh"]["generate"] = "hook-probe";
  hook["top_vertex"] = "auto";
  nlohmann::json k0, k1;
  k0["t"] = 0.0;
  k0["position"] = {top.x(), top.y(), top.z() + 0.005};
  k1["t"] = 0.5;
  k1["position"] = {top.x(), top.y(), top.z() - 0.008};
  hook["motion"]["keyframes"] = nlohmann::json::array({k0, k1});
  nlohmann::json scene;
  scene["schema"] = 1;
  scene["name"] = "xpbd-organ";
  scene["timestep"] = 0.001;
  scene["duration"] = 4.0;
  scene["gravity"] = {0, 0, -9.81};
  scene["tissues"] = nlohmann::json::array({tissue});
  scene["instruments"] = nlohmann::json::array({hook});
  return scene.dump();
}

std::optional<std::string> scene_text(int which) {
  if (which == 0) return test::probe_liver_scene_text(0.5, "sdf");
  if (which == 2) return xpbd_organ_text();
  return held_press_text();
}

/// arg 0: scene (0 probe–liver, 1 held press, 2 xpbd 11.5K organ); arg 1: haptic rate (Hz).
void BM_HapticLoopBesidePhysics(benchmark::State& state) {
  const std::optional<std::string> text = scene_text(static_cast<int>(state.range(0)));
  if (!text) {
    state.SkipWithError("shared meshes absent (probe-liver scene)");
    return;
  }
  RuntimeReport report;
  for (auto _ : state) {
    Scene scene = parse_scene(*text, "bench scene", TROCAR_BENCH_SCENES);
    scene.settings.measure_penetration = false;
    const std::vector<DeviceSpec> devices = scene.devices;
    const Real timestep = scene.timestep;
    Simulation sim(std::move(scene.world), scene.settings);
    drive(sim, timestep, 500);  // warm-up press (the step's first-contact allocations)
    RuntimeSettings settings;
    settings.haptic_rate_hz = double(state.range(1));
    settings.duration = 3.0;
    settings.physics_timestep = timestep;
    std::vector<RuntimeChannel> channels = make_channels(devices, sim.world());
    Runtime runtime(sim, std::move(channels), settings);
    report = runtime.run();
    state.SetIterationTime(report.wall_time);
  }
  const double nominal_us = 1e6 / double(state.range(1));
  state.counters["rate_hz"] = report.rate_hz;
  state.counters["on_time_pct"] = 100 * (1 - report.deadline_miss_fraction);
  state.counters["period_p99_us"] = report.period_us.p99();
  state.counters["period_p99_x"] = report.period_us.p99() / nominal_us;
  state.counters["jitter_p99_us"] = report.jitter_us_p99;
  state.counters["tick_p99_us"] = report.tick_us.p99();
  state.counters["tick_max_us"] = report.tick_us.max();
  state.counters["physics_hz"] = report.physics_rate_hz;
  state.counters["step_median_us"] = report.physics.step.median();
  state.SetLabel(report.warnings.empty() ? "SCHED_FIFO" : "normal scheduling (SCHED_FIFO refused)");
}

/// The bare loop at arg 0 Hz for 3 s: wait_until with the runtime's spin, the runtime's lateness
/// rule, nothing else (no physics thread).
void BM_BareLoop(benchmark::State& state) {
  const auto period_ns = static_cast<std::int64_t>(1e9 / double(state.range(0)));
  const std::int64_t spin = std::min<std::int64_t>(RuntimeSettings{}.spin_ns, period_ns / 2);
  std::uint64_t slots = 0, late = 0;
  double wall = 0;
  for (auto _ : state) {
    const std::string warning = make_current_thread_realtime(49, -1);
    const std::int64_t start = monotonic_ns(), end = start + 3'000'000'000;
    std::int64_t next = start;
    while (next < end) {
      wait_until(next, spin);
      const std::int64_t t0 = monotonic_ns();
      ++slots;
      if (double(t0 - next) > 0.1 * double(period_ns)) ++late;
      next += period_ns;
      while (next + period_ns < t0) {  // skipped slots count as missed, as in the runtime
        next += period_ns;
        ++slots;
        ++late;
      }
    }
    wall = double(monotonic_ns() - start) * 1e-9;
    state.SetIterationTime(wall);
    state.SetLabel(warning.empty() ? "SCHED_FIFO" : "normal scheduling (SCHED_FIFO refused)");
  }
  state.counters["on_time_pct"] = slots > 0 ? 100.0 * (1 - double(late) / double(slots)) : 0;
  state.counters["slots"] = double(slots);
}

BENCHMARK(BM_BareLoop)->Arg(1000)->Arg(4000)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

BENCHMARK(BM_HapticLoopBesidePhysics)
    ->ArgsProduct({{0, 1, 2}, {1000, 4000, 10000}})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace trocar
