#include "trocar/render/viewer.h"

#include <epoxy/gl.h>
// GLFW after epoxy: epoxy provides the GL declarations.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "trocar/core/error.h"
#include "trocar/device/port_device.h"
#include "trocar/render/frame_recorder.h"
#include "trocar/render/offscreen.h"
#include "trocar/render/renderer.h"
#include "trocar/procedure/procedure.h"
#include "trocar/render/task_panel.h"
#include "trocar/render/viewer_input.h"
#include "trocar/render/viewer_panel.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;
const int kHapticCpu = RuntimeSettings{}.haptic_cpu;  // the runtime's default

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// One run of the scene on the runtime (the viewer restarts it on Apply, Reset and Record).
struct Session {
  std::string name;
  CameraSpec camera;     // the one --camera names, chosen before the runtime starts (the
                         // default camera reads the world, which physics then owns)
  CameraSpec orbit;      // the free camera's start
  SceneLook look;          // textures and appearances
  std::unique_ptr<Simulation> sim;
  std::unique_ptr<RecordingWriter> recorder;
  fs::path recording;
  std::unique_ptr<Runtime> runtime;
  std::thread thread;
  RuntimeReport report;
  PortDevice* port = nullptr;
  std::string device;
  ViewSnapshot first;  // drawn until the runtime publishes
  std::unique_ptr<Procedure> procedure;  // the scene's task (null: none); the physics thread's while it runs
  TaskView first_task;                   // shown until the runtime publishes the panel
  double timestep = 1e-3;  // the scene's "timestep": the physics thread's step
  std::vector<std::string> instrument_names;  // for the panel's lines (surgery_status)

  void launch(const ViewerOptions& o, const std::vector<DeviceSpec>& devices, const PortCommand& command) {
    std::vector<RuntimeChannel> channels = make_channels(devices, sim->world());
    port = o.drive >= 0 && std::size_t(o.drive) < channels.size()
               ? dynamic_cast<PortDevice*>(channels[std::size_t(o.drive)].device.get())
               : nullptr;
    if (port) port->set(command);
    device = o.drive >= 0 && std::size_t(o.drive) < channels.size() ? channels[std::size_t(o.drive)].device->specs().name
                                                                     : "scripted";
    RuntimeSettings s;
    s.haptic_rate_hz = o.haptic_rate_hz;
    s.duration = 0;  // until stopped
    s.physics_timestep = timestep;
    s.view_rate_hz = 60;
    s.realtime_scheduling = o.realtime_scheduling;
    s.haptic_cpu = kHapticCpu;
    capture_view(*sim, first);
    runtime = std::make_unique<Runtime>(*sim, std::move(channels), s, recorder.get());
    if (procedure) {
      first_task = procedure->view();
      runtime->set_procedure(procedure.get());
    }
    thread = std::thread([this] { report = runtime->run(); });
  }
  void halt() {
    if (!runtime) return;
    runtime->request_stop();
    if (thread.joinable()) thread.join();
    runtime.reset();
  }
  void finish() {
    halt();
    if (recorder) {
      finish_recording(*recorder, *sim);
      recorder.reset();
    }
  }
  const ViewSnapshot& view() {
    if (runtime && runtime->live().running.load(std::memory_order_acquire)) {
      runtime->views().update();
      if (runtime->views().front().step > 0 || !runtime->views().front().tissues.empty()) return runtime->views().front();
    }
    return first;
  }
  /// The task panel: the runtime's latest, or the task as it stood at the start (null: no task).
  const TaskView* task() {
    if (!procedure) return nullptr;
    if (runtime && runtime->live().running.load(std::memory_order_acquire)) {
      runtime->task_views().update();
      if (!runtime->task_views().front().steps.empty()) return &runtime->task_views().front();
    }
    return &first_task;
  }
};

struct Viewer {
  ViewerOptions options;
  nlohmann::json doc;
  SceneEdits edits;
  RenderOptions render;
  PanelLive live;
  ViewerInput input;
  GLFWwindow* window = nullptr;
  std::unique_ptr<Renderer> renderer;
  std::unique_ptr<Session> session;
  std::vector<DeviceSpec> devices;
  fs::path last_recording;  // the last session recording finished

  /// Builds the scene from the (edited) document and starts it; a bad edit keeps the old session.
  void start(bool record) {
    const std::string text = doc.dump(2);
    Scene scene = parse_scene(text, options.scene.string(), options.scene.parent_path());
    auto next = std::make_unique<Session>();
    next->name = scene.name;
    const std::vector<CameraSpec> cameras = scene.cameras;
    next->look = SceneLook{scene.textures, scene.tissue_appearance, scene.rigid_appearance};
    next->timestep = scene.timestep;
    std::vector<DeviceSpec> next_devices = scene.devices;
    if (options.drive >= 0 && std::size_t(options.drive) < next_devices.size() &&
        !next_devices[std::size_t(options.drive)].given) {
      DeviceSpec& d = next_devices[std::size_t(options.drive)];
      d.given = true;
      d.driver = "mouse";
      d.where = options.scene.string() + ": instruments[" + std::to_string(options.drive) + "] (viewer mouse)";
    }
    scene.settings.measure_penetration = false;  // exact metrics are for studies, not the live loop
    next->sim = std::make_unique<Simulation>(std::move(scene.world), scene.settings);
    for (const InstrumentBody& body : next->sim->world().instruments) next->instrument_names.push_back(body.name);
    if (scene.task)
      next->procedure = std::make_unique<Procedure>(*scene.task, next->sim->world(), scene.zones, scene.landmarks);
    next->camera = select_camera(cameras, next->sim->world(), options.camera);
    next->orbit = default_orbit_camera(next->sim->world());
    if (record) {
      fs::create_directories(options.record_dir);
      char stamp[32];
      const std::time_t now = std::time(nullptr);
      std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
      next->recording = options.record_dir / (next->name + "-" + stamp + ".trec");
      RuntimeSettings rs;
      rs.haptic_rate_hz = options.haptic_rate_hz;
      rs.physics_timestep = scene.timestep;
      next->recorder = std::make_unique<RecordingWriter>(next->recording,
                                                          session_header(options.scene, text, *next->sim, rs));
    }
    if (session) session->finish();
    renderer.reset();
    session = std::move(next);
    devices = std::move(next_devices);
    input.set_command(PortCommand{});
    session->launch(options, devices, input.command());
    renderer = std::make_unique<Renderer>(session->sim->world(), session->look);
    live.recording = record;
    live.recording_path = session->recording.string();
    live.device = session->device;
    live.paused = false;
  }

  /// Ends a recording without resetting: the scene goes on on a fresh runtime.
  void stop_recording() {
    session->finish();
    last_recording = session->recording;
    live.status = "saved " + session->recording.string() + " (trocar score assesses it)";
    session->launch(options, devices, input.command());
    live.recording = false;
  }

  CameraView camera(int w, int h) const {
    if (input.free_camera) return make_camera_view(input.orbit, double(w) / double(std::max(h, 1)));
    return make_camera_view(session->camera, double(w) / double(std::max(h, 1)));
  }
};

ViewerKey glfw_key(int key) {
  switch (key) {
    case GLFW_KEY_W: return ViewerKey::kInsert;
    case GLFW_KEY_S: return ViewerKey::kRetract;
    case GLFW_KEY_A: return ViewerKey::kYawLeft;
    case GLFW_KEY_D: return ViewerKey::kYawRight;
    case GLFW_KEY_UP: return ViewerKey::kPitchUp;
    case GLFW_KEY_DOWN: return ViewerKey::kPitchDown;
    case GLFW_KEY_Q: return ViewerKey::kRollLeft;
    case GLFW_KEY_E: return ViewerKey::kRollRight;
    case GLFW_KEY_SPACE: return ViewerKey::kJaw;
    case GLFW_KEY_C: return ViewerKey::kToggleCamera;
    case GLFW_KEY_P: return ViewerKey::kPause;
    case GLFW_KEY_N: return ViewerKey::kStep;
    case GLFW_KEY_R: return ViewerKey::kReset;
    case GLFW_KEY_F9: return ViewerKey::kRecord;
    case GLFW_KEY_T: return ViewerKey::kFire;      // a tack
    case GLFW_KEY_X: return ViewerKey::kExchange;  // the instrument in the port
    case GLFW_KEY_B: return ViewerKey::kEnergy;    // held: the electrode's pedal (burn)
    case GLFW_KEY_V: return ViewerKey::kSuction;   // held: the suction valve (vacuum)
    case GLFW_KEY_I: return ViewerKey::kIrrigate;  // held: the irrigation valve
    default: return ViewerKey::kOther;
  }
}

Viewer* viewer_of(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

void handle_key_action(Viewer& v, ViewerKey action) {
  if (action == ViewerKey::kPause) {
    v.live.paused = !v.live.paused;
    v.session->runtime->set_paused(v.live.paused);
  } else if (action == ViewerKey::kStep) {
    v.live.paused = true;
    v.session->runtime->set_paused(true);
    v.session->runtime->step_once();
  } else if (action == ViewerKey::kReset) {
    v.start(false);
  } else if (action == ViewerKey::kRecord) {
    if (v.live.recording) v.stop_recording();
    else v.start(true);
  }
}

void install_callbacks(GLFWwindow* window) {
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
    ViewerInput& input = viewer_of(w)->input;
    double x = 0, y = 0;
    if (!input.last_cursor(x, y)) glfwGetCursorPos(w, &x, &y);  // no cursor event yet
    input.mouse_button(button, action == GLFW_PRESS, x, y, ImGui::GetIO().WantCaptureMouse);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) { viewer_of(w)->input.cursor(x, y); });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
    viewer_of(w)->input.scroll(dy, ImGui::GetIO().WantCaptureMouse);
  });
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    if (action == GLFW_REPEAT || ImGui::GetIO().WantCaptureKeyboard) return;
    if (key == GLFW_KEY_ESCAPE) {  // as the window's close button
      glfwSetWindowShouldClose(w, GLFW_TRUE);
      return;
    }
    Viewer& v = *viewer_of(w);
    handle_key_action(v, v.input.key(glfw_key(key), action == GLFW_PRESS));
  });
}

/// A script's "settle": waits until the runtime has taken in the input so far, counted, not
/// timed: two haptic ticks (the port command sensed and handed to physics), then 200 physics
/// steps (the driven instrument reaches its commanded pose). Wall time only bounds it (30 s).
void settle(Viewer& v) {
  if (v.session->port) v.session->port->set(v.input.command());
  const RuntimeLive& live = v.session->runtime->live();
  const auto wait_for = [](const auto& done, const char* what) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!done()) {
      if (std::chrono::steady_clock::now() > limit) throw Error(std::string("trocar view: settle: ") + what);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  const std::uint64_t ticks = live.ticks.load();
  wait_for([&] { return live.ticks.load() >= ticks + 2; }, "the haptic loop did not tick twice within 30 s");
  if (v.live.paused) return;  // paused physics takes the command at its next step
  const std::uint64_t steps = live.physics_steps.load();
  wait_for([&] { return live.physics_steps.load() >= steps + 200; }, "physics did not run 200 steps within 30 s");
}

void play(Viewer& v, const InjectedEvent& e) {
  switch (e.kind[0]) {
    case 'd': v.input.mouse_button(e.button, true, e.x, e.y); break;
    case 'u': v.input.mouse_button(e.button, false, e.x, e.y); break;
    case 'm': v.input.cursor(e.x, e.y); break;
    case 's': e.kind == "settle" ? settle(v) : v.input.scroll(e.y); break;
    default: handle_key_action(v, v.input.key(e.key, e.kind == "key")); break;
  }
}

/// GL objects first, while the context is current; then ImGui, the window, GLFW.
void close_window(Viewer& v) {
  v.renderer.reset();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(v.window);
  glfwTerminate();
}

Image read_window(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  std::vector<std::uint8_t> rgb(std::size_t(w) * std::size_t(h) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  img.rgb.resize(rgb.size());
  const std::size_t row = std::size_t(w) * 3;
  for (int y = 0; y < h; ++y) std::copy_n(&rgb[std::size_t(h - 1 - y) * row], row, &img.rgb[std::size_t(y) * row]);
  return img;
}

}  // namespace

namespace {

/// Opens the window with an OpenGL 3.3 core context, our input callbacks and ImGui.
void open_window(Viewer& v) {
  const ViewerOptions& options = v.options;
  keep_rendering_off_cpu(kHapticCpu);
  glfwSetErrorCallback([](int, const char* what) { std::fprintf(stderr, "trocar view: glfw: %s\n", what); });
  if (!glfwInit())
    throw Error("no display: trocar view needs a window system (set DISPLAY, or run under xvfb-run); "
                "for headless frames use trocar run SCENE --frames DIR");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, options.samples);
  v.window = glfwCreateWindow(options.width, options.height, ("trocar — " + options.scene.filename().string()).c_str(),
                              nullptr, nullptr);
  if (!v.window) {
    glfwTerminate();
    throw Error("trocar view: cannot open an OpenGL 3.3 core window (is the display's GL too old?)");
  }
  glfwMakeContextCurrent(v.window);
  glfwSwapInterval(1);
  glfwSetWindowUserPointer(v.window, &v);
  install_callbacks(v.window);  // before ImGui's, which chain to them

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(v.window, true);
  ImGui_ImplOpenGL3_Init("#version 330");
}

/// The frame loop and what it measures for the panel and the report.
class FrameLoop {
 public:
  FrameLoop(Viewer& v, std::vector<InjectedEvent> events) : v_(v), events_(std::move(events)) {}

  /// Draws frames until the window closes or a quit option says so.
  void run() {
    while (!glfwWindowShouldClose(v_.window)) {
      const double now = seconds_since(t0_);
      const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_).count();
      last_ = std::chrono::steady_clock::now();
      glfwPollEvents();
      take_input(now, dt);
      const ViewSnapshot& snap = v_.session->view();
      track_driven_instrument(snap);
      update_live_figures(snap, now, dt);
      const bool quitting = (v_.options.quit_after > 0 && now >= v_.options.quit_after) ||
                            (v_.options.quit_after_frames > 0 && frames_ + 1 >= std::size_t(v_.options.quit_after_frames));
      if (!draw_frame(snap, quitting)) break;
    }
    wall_ = seconds_since(t0_);
  }

  /// The report's JSON, once the session has finished.
  nlohmann::json report() const {
    const ViewerOptions& options = v_.options;
    const RuntimeReport& r = v_.session->report;
    const PortCommand& c = v_.input.command();
    return {
        {"scene", v_.session->name},
        {"frames", frames_},
        {"wall_time_s", wall_},
        {"fps", wall_ > 0 ? double(frames_) / wall_ : 0},
        {"size", {options.width, options.height}},
        {"samples", options.samples},
        {"renderer", std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER)))},
        {"haptic",
         {{"rate_nominal_hz", options.haptic_rate_hz},
          {"rate_hz", r.rate_hz},
          {"ticks", r.ticks},
          {"deadline_miss_fraction", r.deadline_miss_fraction},
          {"period_us_p99", r.period_us.p99()},
          {"warnings", r.warnings}}},
        {"physics", {{"steps", r.physics_steps}, {"rate_hz", r.physics_rate_hz}, {"step_us_median", r.physics.step.median()}}},
        {"driven_instrument",
         {{"index", options.drive},
          {"device", v_.session->device},
          {"start", {start_position_.x(), start_position_.y(), start_position_.z()}},
          {"end", {end_position_.x(), end_position_.y(), end_position_.z()}},
          {"travel_m", (end_position_ - start_position_).norm()},
          {"command", {{"yaw", c.yaw}, {"pitch", c.pitch}, {"depth", c.depth}, {"roll", c.roll}, {"jaw", c.jaw}}}}},
        {"events_played", next_event_},
        {"last_recording", v_.last_recording.string()},
    };
  }

 private:
  /// The script's events due by now (or by this frame), held keys, the command to the driver.
  /// A frame script advances held keys by 1/60 s a frame, so that it needs no wall clock at all.
  void take_input(double now, double dt) {
    const bool by_frame = !events_.empty() && events_.front().frame >= 0;
    while (next_event_ < events_.size() &&
           (by_frame ? std::size_t(events_[next_event_].frame) <= frames_ : events_[next_event_].time <= now))
      play(v_, events_[next_event_++]);
    v_.input.advance(by_frame ? 1.0 / 60 : dt);
    if (v_.input.take_changed() && v_.session->port) v_.session->port->set(v_.input.command());
  }

  void track_driven_instrument(const ViewSnapshot& snap) {
    const int drive = v_.options.drive;
    if (drive < 0 || std::size_t(drive) >= snap.instruments.size()) return;
    end_position_ = snap.instruments[std::size_t(drive)].pose.translation;
    if (!have_start_) start_position_ = end_position_, have_start_ = true;
  }

  /// The panel's rates (over the last quarter and half second), misses and timing plots.
  void update_live_figures(const ViewSnapshot& snap, double now, double dt) {
    PanelLive& live = v_.live;
    const RuntimeLive& rl = v_.session->runtime->live();
    const std::uint64_t ticks = rl.ticks.load(std::memory_order_relaxed);
    if (now - last_tick_time_ >= 0.25) {
      live.haptic_rate_hz = double(ticks - std::min(ticks, last_ticks_)) / (now - last_tick_time_);
      last_ticks_ = ticks;
      last_tick_time_ = now;
    }
    live.deadline_miss_fraction = ticks ? double(rl.late_ticks.load(std::memory_order_relaxed)) / double(ticks) : 0;
    const double run_s = double(std::chrono::steady_clock::now().time_since_epoch().count() -
                                rl.started_ns.load(std::memory_order_relaxed)) * 1e-9;
    live.physics_rate_hz = run_s > 0 ? double(rl.physics_steps.load(std::memory_order_relaxed)) / run_s : 0;
    live.sim_time = snap.time;
    live.step_us.add(float(snap.timings.step));
    live.broad_us.add(float(snap.timings.broad_phase));
    live.narrow_us.add(float(snap.timings.narrow_phase));
    live.response_us.add(float(snap.timings.response));
    live.deformation_us.add(float(snap.timings.deformation));
    live.haptic_khz.add(float(live.haptic_rate_hz * 1e-3));
    live.frame_ms.add(float(dt * 1e3));
    if (now - fps_since_ >= 0.5) {
      live.fps = double(frames_ - fps_frames_) / (now - fps_since_);
      fps_frames_ = frames_;
      fps_since_ = now;
    }
    live.free_camera = v_.input.free_camera;
    live.surgery = surgery_status(snap, v_.session->instrument_names);
  }

  /// Draws the scene and the panel, takes a screenshot when asked, swaps; then carries out the
  /// panel's actions. False when this was the last frame.
  bool draw_frame(const ViewSnapshot& snap, bool quitting) {
    const ViewerOptions& options = v_.options;
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(v_.window, &fw, &fh);
    v_.renderer->draw(snap, v_.camera(fw, fh), v_.render, fw, fh);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    PanelActions a;
    if (options.panel) a = draw_panel(v_.edits, v_.render, v_.live);
    if (const TaskView* task = v_.session->task()) {  // the scene's task, as the physics thread last published it
      const float display = ImGui::GetIO().DisplaySize.x;  // window units (the framebuffer's may differ)
      const float width = std::clamp(0.3f * display, 200.0f, 420.0f);
      draw_task_window(*task, display - width - 8, 8, width, false);
    }
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++frames_;
    if (a.screenshot || (quitting && !options.screenshot.empty())) {
      const fs::path shot = quitting && !options.screenshot.empty() ? options.screenshot : fs::path("trocar-shot.png");
      write_png(shot.c_str(), read_window(fw, fh));
      v_.live.status = "screenshot " + shot.string();
    }
    glfwSwapBuffers(v_.window);
    if (quitting) return false;
    apply_panel_actions(a);
    return true;
  }

  /// Pause, step, camera, reset, record and Apply; a rejected edit is shown in the panel and the
  /// old scene runs on.
  void apply_panel_actions(const PanelActions& a) {
    try {
      if (a.pause) handle_key_action(v_, ViewerKey::kPause);
      if (a.step) handle_key_action(v_, ViewerKey::kStep);
      if (a.camera) v_.input.free_camera = !v_.input.free_camera;
      if (a.reset) v_.start(false);
      if (a.record) handle_key_action(v_, ViewerKey::kRecord);
      if (a.apply) {
        nlohmann::json edited = v_.doc;
        apply_edits(edited, v_.edits, v_.options.drive);
        std::swap(v_.doc, edited);
        try {
          v_.start(false);
          v_.live.status = "applied";
        } catch (const Error&) {
          std::swap(v_.doc, edited);  // keep the scene that worked
          throw;
        }
      }
    } catch (const Error& e) {
      v_.live.status = e.what();
    }
  }

  Viewer& v_;
  std::vector<InjectedEvent> events_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now(), last_ = t0_;
  std::size_t next_event_ = 0, frames_ = 0, fps_frames_ = 0;
  double fps_since_ = 0, wall_ = 0;
  std::uint64_t last_ticks_ = 0;
  double last_tick_time_ = 0;
  Vec3 start_position_ = Vec3::Zero(), end_position_ = Vec3::Zero();
  bool have_start_ = false;
};

void write_report(const fs::path& file, const nlohmann::json& report) {
  if (file.empty()) return;
  std::ofstream out(file);
  if (!out) throw Error(file.string() + ": cannot write the viewer report");
  out << report.dump(2) << "\n";
}

void print_summary(const nlohmann::json& report) {
  std::printf("view: %s, %zu frames in %.1f s (%.1f fps); haptic %.0f Hz, deadline misses %.3f %%\n",
              report["scene"].get<std::string>().c_str(), report["frames"].get<std::size_t>(),
              report["wall_time_s"].get<double>(), report["fps"].get<double>(),
              report["haptic"]["rate_hz"].get<double>(), 100 * report["haptic"]["deadline_miss_fraction"].get<double>());
}

}  // namespace

int run_viewer(const ViewerOptions& options, std::filesystem::path* last_recording) {
  Viewer v;
  v.options = options;
  const std::string text = read_scene_text(options.scene);
  parse_scene(text, options.scene.string(), options.scene.parent_path());  // a bad scene fails before a window opens
  v.doc = nlohmann::json::parse(text);
  v.edits = edits_from(v.doc, options.drive);
  std::vector<InjectedEvent> events;
  if (!options.inject.empty()) events = read_injected_events(options.inject.string());
  open_window(v);
  nlohmann::json report;
  try {
    v.start(false);
    v.input.orbit = v.session->orbit;
    FrameLoop loop(v, std::move(events));
    loop.run();
    v.session->finish();
    if (!v.session->recording.empty()) v.last_recording = v.session->recording;
    report = loop.report();
  } catch (...) {
    if (v.session) v.session->finish();
    close_window(v);
    throw;
  }
  close_window(v);
  write_report(options.report, report);
  print_summary(report);
  if (!v.last_recording.empty()) std::printf("session recording: %s (trocar score assesses it)\n", v.last_recording.c_str());
  if (last_recording) *last_recording = v.last_recording;
  return 0;
}

}  // namespace trocar
