#include "trocar/render/frame_recorder.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "trocar/core/error.h"
#ifdef TROCAR_RENDER_TASK_PANEL
#include "trocar/render/task_panel.h"
#endif

extern char** environ;

namespace trocar {

CameraSpec select_camera(const std::vector<CameraSpec>& scene_cameras, const World& world, const std::string& name) {
  for (const CameraSpec& c : scene_cameras)
    if (c.name == name) return c;
  if (name == "scope" || name.empty()) return scene_cameras.empty() ? default_camera(world) : scene_cameras.front();
  if (name == "orbit") return default_orbit_camera(world);
  std::string known = "scope, orbit";
  for (const CameraSpec& c : scene_cameras)
    if (c.name != "scope" && c.name != "orbit") known += ", " + c.name;
  throw Error("--camera: no camera \"" + name + "\" (known: " + known + ")");
}

FrameRecorder::FrameRecorder(const World& world, const FrameSettings& settings) : settings_(settings) {
  if (!(settings_.fps > 0 && settings_.fps <= 1000)) throw Error("--fps: must be in (0, 1000]");
  std::error_code ec;
  std::filesystem::create_directories(settings_.dir, ec);
  if (ec) throw Error(settings_.dir.string() + ": cannot create the frames folder: " + ec.message());
  context_ = std::make_unique<OffscreenContext>(settings_.width, settings_.height, settings_.samples);
  renderer_ = std::make_unique<Renderer>(
      world, SceneLook{settings_.textures, settings_.tissue_appearance, settings_.rigid_appearance});
  view_ = make_camera_view(settings_.camera, double(settings_.width) / double(settings_.height));
}

FrameRecorder::~FrameRecorder() {
  panel_.reset();  // GL objects go while the context is current
  renderer_.reset();
  context_.reset();
}

std::filesystem::path FrameRecorder::frame_path(std::size_t k) const {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04zu.png", k);
  return settings_.dir / name;
}

bool FrameRecorder::draws_task_panel() {
#ifdef TROCAR_RENDER_TASK_PANEL
  return true;
#else
  return false;
#endif
}

void FrameRecorder::on_step(const Simulation& sim, const TaskView* task) {
  // Frame k shows time k / fps; a step of dt can pass several frame times at low step rates.
  while (double(frames_) / settings_.fps <= sim.time() + 1e-9) {
    render(sim, task, frame_path(frames_));
    ++frames_;
  }
}

void FrameRecorder::render_to(const Simulation& sim, const TaskView* task, const std::filesystem::path& file) {
  render(sim, task, file);
}

void FrameRecorder::render(const Simulation& sim, const TaskView* task, const std::filesystem::path& file) {
  const auto t0 = std::chrono::steady_clock::now();
  capture_view(sim, snapshot_);
  context_->bind();
  renderer_->draw(snapshot_, view_, settings_.options, settings_.width, settings_.height);
#ifdef TROCAR_RENDER_TASK_PANEL
  if (task) {
    if (!panel_) panel_ = std::make_shared<TaskPanelOverlay>();
    panel_->draw(*task, settings_.width, settings_.height);
  }
#else
  (void)task;
#endif
  context_->read(image_);
  write_png(file.c_str(), image_);
  total_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string encode_video(const std::filesystem::path& dir, double fps, const std::filesystem::path& video) {
  const std::string rate = std::to_string(fps);
  const std::string input = (dir / "frame_%04d.png").string();
  const std::string output = video.string();
  // Odd sizes are padded: yuv420p needs even ones.
  const char* argv[] = {"ffmpeg", "-loglevel", "error", "-y", "-framerate", rate.c_str(), "-i", input.c_str(),
                        "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p",
                        output.c_str(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, const_cast<char* const*>(argv), environ);
  if (rc != 0)
    return "ffmpeg is not installed (Debian: apt-get install ffmpeg); the PNG frames are in " + dir.string();
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return "ffmpeg: waitpid failed";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    return "ffmpeg is not installed (Debian: apt-get install ffmpeg); the PNG frames are in " + dir.string();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return "ffmpeg failed (exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
           ") encoding " + output;
  return "";
}

}  // namespace trocar
