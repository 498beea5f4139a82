#include "view_command.h"

#include <filesystem>
#include <memory>
#include <string>

#include "frame_size.h"
#include "score_command.h"
#include "trocar/core/error.h"
#ifdef TROCAR_HAVE_VIEWER
#include "trocar/render/viewer.h"
#endif

namespace trocar::cli {

void add_view_command(CLI::App& app, int& exit_code) {
  struct Options {
    std::string scene, camera = "scope", screenshot, report, inject, record_dir = "out", size = "1280x720", expert;
    bool score = false;
    double rate = 1000, quit_after = 0;
    int drive = 0, samples = 4, quit_after_frames = 0;
    bool no_panel = false, no_realtime = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("view", "Open the laparoscope view of a scene running in real time (needs a display)");
  cmd->add_option("scene", o->scene, "Scene file (JSON, docs/scene.md)")->required();
  cmd->add_option("--camera", o->camera, "Camera: scope (default), orbit, or a scene camera's name");
  cmd->add_option("--size", o->size, "Window size WIDTHxHEIGHT (default 1280x720)");
  cmd->add_option("--haptic-rate", o->rate, "Haptic rate in Hz (default 1000)")->check(CLI::Range(1.0, 100000.0));
  cmd->add_option("--drive", o->drive, "Instrument the mouse drives when the scene names no device for it (-1: none)")
      ->check(CLI::Range(-1, 3));
  cmd->add_option("--quit-after", o->quit_after, "Quit after this many seconds")->check(CLI::NonNegativeNumber);
  cmd->add_option("--quit-after-frames", o->quit_after_frames, "Quit after drawing this many frames")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--screenshot", o->screenshot, "Write a PNG of the window just before quitting");
  cmd->add_option("--report", o->report, "Write a JSON report (frame rate, haptic rate, misses) when quitting");
  cmd->add_option("--inject", o->inject, "Play a script of mouse and key events (docs/render.md)");
  cmd->add_option("--record-dir", o->record_dir, "Folder for session recordings (the Record button; default out)");
  cmd->add_option("--samples", o->samples, "Multisampling (default 4; 0 is twice as fast under Mesa's llvmpipe)")
      ->check(CLI::Range(0, 16));
  cmd->add_flag("--no-panel", o->no_panel, "Hide the settings panel");
  cmd->add_flag("--score", o->score, "On quitting, score the last session recorded (the Record button): trocar score");
  cmd->add_option("--expert", o->expert, "With --score: the expert sessions (a folder of recordings or a reference file)");
  cmd->add_flag("--no-realtime-scheduling", o->no_realtime, "Do not ask for SCHED_FIFO and CPU pinning");
  cmd->callback([o, &exit_code]() {
#ifdef TROCAR_HAVE_VIEWER
    ViewerOptions v;
    v.scene = o->scene;
    parse_frame_size(o->size, "--size", v.width, v.height);
    v.camera = o->camera;
    v.haptic_rate_hz = o->rate;
    v.drive = o->drive;
    v.quit_after = o->quit_after;
    v.quit_after_frames = o->quit_after_frames;
    v.screenshot = o->screenshot;
    v.report = o->report;
    v.inject = o->inject;
    v.record_dir = o->record_dir;
    v.panel = !o->no_panel;
    v.samples = o->samples;
    v.realtime_scheduling = !o->no_realtime;
    std::filesystem::path recorded;
    exit_code = run_viewer(v, &recorded);
    if (o->score && !recorded.empty()) score_session(recorded.string(), o->expert, "", false);
#else
    (void)exit_code;
    throw Error("view: this trocar was built without the viewer (install libglfw3-dev, libimgui-dev, libepoxy-dev and "
                "rebuild; scripts/setup does)");
#endif
  });
}

}  // namespace trocar::cli
