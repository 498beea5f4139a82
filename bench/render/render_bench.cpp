// Rendering: the cost of one offscreen frame (EGL, Mesa's llvmpipe here), and the haptic loop's
// timing with a renderer drawing the runtime's snapshots as fast as it can beside it — the
// check that rendering never blocks the physics or the haptic thread. The renderer
// thread keeps off the haptic core (keep_rendering_off_cpu) exactly as `trocar view` does.
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "sim/probe_liver_scene.h"
#include "trocar/render/frame_recorder.h"
#include "trocar/render/offscreen.h"
#include "trocar/render/renderer.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

std::string shipped(const char* name) {
  std::ifstream in(std::string(TROCAR_BENCH_SCENES) + "/" + name);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The shipped press scene with its probe pressed 2.25 cm into the lobe within 0.5 s and held.
std::string held_press_text() {
  nlohmann::json scene = nlohmann::json::parse(shipped("probe_press_slide.json"));
  scene["instruments"][0]["motion"] = {{"keyframes",
                                        {{{"t", 0.0}, {"position", {0, 0, 0.045}}},
                                         {{"t", 0.5}, {"position", {0, 0, 0.0225}}}}}};
  return scene.dump();
}

/// 0: the default scene (hernia); 1: the held press; 2: probe–liver (shared meshes).
std::optional<std::string> scene_text(int which) {
  if (which == 0) return shipped("hernia.json");
  if (which == 1) return held_press_text();
  return test::probe_liver_scene_text(0.5, "obb");
}

const char* scene_label(int which) { return which == 0 ? "hernia" : which == 1 ? "held press" : "probe-liver"; }

/// arg 0: scene; arg 1: MSAA samples. One 1280×720 frame: draw + read back (no PNG).
void BM_RenderFrame1280x720(benchmark::State& state) {
  const auto text = scene_text(int(state.range(0)));
  if (!text) return state.SkipWithError("shared meshes absent");
  Scene scene = parse_scene(*text, "bench scene", TROCAR_BENCH_SCENES);
  const std::vector<CameraSpec> cameras = scene.cameras;
  Simulation sim(std::move(scene.world), scene.settings);
  drive(sim, scene.timestep, 500);
  OffscreenContext ctx(1280, 720, int(state.range(1)));
  Renderer renderer(sim.world());
  const CameraView cam = make_camera_view(select_camera(cameras, sim.world(), "scope"), 1280.0 / 720.0);
  ViewSnapshot snap;
  capture_view(sim, snap);
  Image img;
  std::size_t triangles = 0;
  for (const auto& t : sim.world().tissues) triangles += t->settings.triangles.size();
  for (auto _ : state) {
    ctx.bind();
    renderer.draw(snap, cam, RenderOptions{}, 1280, 720);
    ctx.read(img);
    benchmark::DoNotOptimize(img.rgb.data());
  }
  state.counters["fps"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["tissue_triangles"] = double(triangles);
  state.SetLabel(std::string(scene_label(int(state.range(0)))) + ", " + ctx.description());
}
BENCHMARK(BM_RenderFrame1280x720)->ArgsProduct({{0, 1, 2}, {1, 4}})->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// arg 0: scene; arg 1: 1 = a renderer draws the runtime's snapshots at 1280×720 beside it.
/// 3 s of the runtime at 1 kHz, multirate, after a 0.5 s warm-up press.
void BM_HapticLoopBesideRenderer(benchmark::State& state) {
  const auto text = scene_text(int(state.range(0)));
  if (!text) return state.SkipWithError("shared meshes absent");
  const bool rendering = state.range(1) != 0;
  RuntimeReport report;
  double fps = 0;
  for (auto _ : state) {
    Scene scene = parse_scene(*text, "bench scene", TROCAR_BENCH_SCENES);
    scene.settings.measure_penetration = false;
    const std::vector<DeviceSpec> devices = scene.devices;
    const std::vector<CameraSpec> cameras = scene.cameras;
    const Real timestep = scene.timestep;
    Simulation sim(std::move(scene.world), scene.settings);
    drive(sim, timestep, 500);
    RuntimeSettings settings;
    settings.haptic_rate_hz = 1000;
    settings.duration = 3.0;
    settings.physics_timestep = timestep;
    settings.view_rate_hz = 60;
    Runtime runtime(sim, make_channels(devices, sim.world()), settings);
    const CameraSpec camera = select_camera(cameras, sim.world(), "scope");
    std::atomic<bool> done{false};
    std::size_t frames = 0;
    double render_s = 0;
    std::thread renderer_thread;
    if (rendering)
      renderer_thread = std::thread([&] {
        keep_rendering_off_cpu(settings.haptic_cpu);
        OffscreenContext ctx(1280, 720, 4);
        Renderer r(sim.world());  // reads only the immutable geometry (rest positions, meshes)
        const CameraView cam = make_camera_view(camera, 1280.0 / 720.0);
        Image img;
        while (!runtime.live().running.load(std::memory_order_acquire) && !done.load()) std::this_thread::yield();
        const auto t0 = std::chrono::steady_clock::now();
        while (!done.load(std::memory_order_acquire) && runtime.live().running.load(std::memory_order_acquire)) {
          runtime.views().update();
          ctx.bind();
          r.draw(runtime.views().front(), cam, RenderOptions{}, 1280, 720);
          ctx.read(img);
          ++frames;
        }
        render_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      });
    report = runtime.run();
    done.store(true, std::memory_order_release);
    if (renderer_thread.joinable()) renderer_thread.join();
    fps = render_s > 0 ? double(frames) / render_s : 0;
    state.SetIterationTime(report.wall_time);
  }
  state.counters["rate_hz"] = report.rate_hz;
  state.counters["on_time_pct"] = 100 * (1 - report.deadline_miss_fraction);
  state.counters["period_p99_us"] = report.period_us.p99();
  state.counters["tick_p99_us"] = report.tick_us.p99();
  state.counters["physics_hz"] = report.physics_rate_hz;
  state.counters["render_fps"] = fps;
  state.SetLabel(std::string(scene_label(int(state.range(0)))) + (rendering ? ", renderer beside" : ", no renderer") +
                 (report.warnings.empty() ? "" : ", normal scheduling (SCHED_FIFO refused)"));
}
BENCHMARK(BM_HapticLoopBesideRenderer)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace trocar
