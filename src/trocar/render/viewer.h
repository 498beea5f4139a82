#pragma once
/// `trocar view SCENE`: a window with the laparoscope view of a scene running on the real-time
/// runtime (docs/render.md). The mouse and keyboard drive an instrument through its port (the
/// "mouse" driver) unless the scene names a device for it; an ImGui panel edits the material,
/// response, broad phase, integrator, time step and force scale (applied by restarting the
/// scene), shows live timing graphs, the haptic rate and deadline misses, and has pause, step,
/// reset and record.
#include <filesystem>
#include <string>


namespace trocar {

/// Command-line options of the viewer.
struct ViewerOptions {
  std::filesystem::path scene;      ///< scene file
  int width = 1280;                 ///< window size (pixels)
  int height = 720;
  std::string camera = "scope";     ///< scope, orbit, or a scene camera's name
  double haptic_rate_hz = 1000;     ///< haptic loop rate
  int drive = 0;                    ///< instrument the mouse drives (−1: none, all scripted)
  double quit_after = 0;            ///< s of wall-clock time, then quit (0: run until closed)
  int quit_after_frames = 0;        ///< frames drawn, then quit (0: no limit)
  std::filesystem::path screenshot; ///< PNG of the window written just before quitting
  std::filesystem::path report;     ///< JSON: frames, frame rate, haptic rate, misses, instrument travel
  std::filesystem::path inject;     ///< event script (viewer_input.h) played as if from the window
  std::filesystem::path record_dir = "out";  ///< where Record writes session recordings
  int samples = 4;                  ///< multisampling of the window (0: none; halves the cost under llvmpipe)
  bool panel = true;                ///< show the settings panel
  bool realtime_scheduling = true;  ///< SCHED_FIFO and pinning for the runtime's threads
};

/// Opens the window and runs until it is closed (or quit_after). Throws trocar::Error when there
/// is no display ("no display: ... use trocar run --frames for headless frames") or the scene is bad.
/// Returns 0 (failures throw).
/// `last_recording` (may be null): set to the last session recording finished ("" when none).
int run_viewer(const ViewerOptions& options, std::filesystem::path* last_recording = nullptr);

}  // namespace trocar
