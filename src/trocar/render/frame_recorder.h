#pragma once
/// Headless frames of an offline run (`trocar run SCENE --frames DIR [--fps] [--size] [--camera]
/// [--video FILE.mp4]`): PNGs rendered through surfaceless EGL at fixed simulated-time intervals,
/// then optionally encoded by ffmpeg.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "trocar/scene/camera.h"
#include "trocar/render/offscreen.h"
#include "trocar/procedure/task_view.h"
#include "trocar/render/renderer.h"
#include "trocar/scene/appearance.h"
#include "trocar/sim/simulation.h"

namespace trocar {

/// The camera called `name`: one of the scene's, or "scope" (the scene's first camera, or
/// default_camera when it has none), or "orbit". Throws trocar::Error listing the names known.
CameraSpec select_camera(const std::vector<CameraSpec>& scene_cameras, const World& world, const std::string& name);

/// What to render.
struct FrameSettings {
  std::filesystem::path dir;      ///< folder for frame_0000.png …
  double fps = 30;                ///< frames per simulated second
  int width = 1280;               ///< pixels
  int height = 720;               ///< pixels
  CameraSpec camera;              ///< from select_camera
  RenderOptions options;          ///< overlays
  int samples = 4;                ///< multisampling
  std::vector<std::filesystem::path> textures;  ///< per tissue (Scene::textures)
  std::vector<Appearance> tissue_appearance;    ///< per tissue (Scene::tissue_appearance)
  std::vector<Appearance> rigid_appearance;     ///< per rigid (Scene::rigid_appearance)
};

class TaskPanelOverlay;

/// Renders a Simulation's frames as it steps.
class FrameRecorder {
 public:
  /// Creates the folder and the EGL context (throws trocar::Error naming what failed).
  FrameRecorder(const World& world, const FrameSettings& settings);
  ~FrameRecorder();
  /// Renders every frame whose time (k / fps) the simulation has reached since the last call;
  /// with a task, its panel drawn at the top right of each (where draws_task_panel()).
  void on_step(const Simulation& sim, const TaskView* task = nullptr);
  /// Renders the simulation as it is now into `file` (a PNG), outside the fps sequence: the
  /// moment of an event (the trainee report's frames of errors).
  void render_to(const Simulation& sim, const TaskView* task, const std::filesystem::path& file);
  /// Whether this build draws the task panel into frames (Dear ImGui was found).
  static bool draws_task_panel();
  /// Frames written so far.
  std::size_t frames() const { return frames_; }
  /// The path of frame k.
  std::filesystem::path frame_path(std::size_t k) const;
  /// The GL renderer in use ("llvmpipe …").
  std::string renderer_description() const { return context_->description(); }
  /// Mean wall-clock milliseconds per frame (render + read-back + PNG).
  double mean_frame_ms() const { return frames_ ? total_ms_ / double(frames_) : 0; }

 private:
  FrameSettings settings_;
  std::unique_ptr<OffscreenContext> context_;
  std::unique_ptr<Renderer> renderer_;
  // Made on the first frame with a task. Shared only so that this header and a build without
  // Dear ImGui need not see the type complete (the deleter is bound where it is made).
  std::shared_ptr<TaskPanelOverlay> panel_;
  CameraView view_;
  ViewSnapshot snapshot_;
  Image image_;
  std::size_t frames_ = 0;
  double total_ms_ = 0;
  void render(const Simulation& sim, const TaskView* task, const std::filesystem::path& file);
};

/// Encodes dir/frame_%04d.png at fps into an H.264 MP4 with ffmpeg. Returns "" on success, else
/// why not (ffmpeg missing: a clear sentence; a failure: its exit status).
std::string encode_video(const std::filesystem::path& dir, double fps, const std::filesystem::path& video);

}  // namespace trocar
