#pragma once
/// The task panel (docs/render.md, "The task panel"): the task's steps with their state and the
/// events so far, as a Dear ImGui window — inside the viewer's ImGui frame, and drawn headless
/// into the frames of `trocar run --frames` by ImGui's OpenGL 3 backend with no window. Built with
/// the renderer when Dear ImGui is found (FrameRecorder::draws_task_panel says whether it was).
#include <cstddef>

#include "trocar/procedure/task_view.h"

struct ImGuiContext;

namespace trocar {

/// Draws the panel as an ImGui window at (x, y) pixels from the top left, `width` wide, its
/// height fitted to the content (call between ImGui::NewFrame and ImGui::Render). `pinned`: the
/// window stays there (headless); else the user may move it after the first frame (the viewer).
/// Shows the last `max_events` events.
void draw_task_window(const TaskView& task, float x, float y, float width, bool pinned, std::size_t max_events = 8);

/// Dear ImGui on a context of its own with its OpenGL 3 backend, drawing the panel into the
/// bound framebuffer of the current OpenGL 3.3 context (an OffscreenContext): no window, no
/// display, io.DisplaySize set by hand.
class TaskPanelOverlay {
 public:
  /// Needs a current GL context. Throws trocar::Error when the backend cannot start.
  TaskPanelOverlay();
  ~TaskPanelOverlay();
  TaskPanelOverlay(const TaskPanelOverlay&) = delete;
  TaskPanelOverlay& operator=(const TaskPanelOverlay&) = delete;

  /// Draws `task` at the top right of a width × height framebuffer, over what is there.
  void draw(const TaskView& task, int width, int height);

 private:
  ImGuiContext* context_ = nullptr;
  bool laid_out_ = false;  // ImGui sizes a new window on its first frame and shows it from the second
};

}  // namespace trocar
