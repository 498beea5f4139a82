#include "trocar/render/task_panel.h"

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <string>

#include "trocar/core/error.h"

namespace trocar {
namespace {

const ImVec4 kDoneColour(0.45f, 0.90f, 0.45f, 1.0f);
const ImVec4 kActiveColour(1.00f, 0.85f, 0.30f, 1.0f);
const ImVec4 kErrorColour(1.00f, 0.35f, 0.30f, 1.0f);

void wrapped(const ImVec4& colour, const std::string& text) {
  ImGui::PushStyleColor(ImGuiCol_Text, colour);
  ImGui::TextWrapped("%s", text.c_str());
  ImGui::PopStyleColor();
}

/// Makes `context` current for its scope and puts the previous one back after.
class CurrentContext {
 public:
  explicit CurrentContext(ImGuiContext* context) : previous_(ImGui::GetCurrentContext()) {
    ImGui::SetCurrentContext(context);
  }
  ~CurrentContext() { ImGui::SetCurrentContext(previous_); }
  CurrentContext(const CurrentContext&) = delete;
  CurrentContext& operator=(const CurrentContext&) = delete;

 private:
  ImGuiContext* previous_;
};

}  // namespace

void draw_task_window(const TaskView& task, float x, float y, float width, bool pinned, std::size_t max_events) {
  const ImGuiCond cond = pinned ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
  ImGui::SetNextWindowPos(ImVec2(x, y), cond);
  ImGui::SetNextWindowSize(ImVec2(width, 0), ImGuiCond_Always);  // height 0: fitted to the content
  ImGui::SetNextWindowBgAlpha(0.78f);
  const std::string title = (task.title.empty() ? std::string("task") : task.title) + "###task";
  ImGuiWindowFlags flags = ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
  if (pinned) flags |= ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoInputs;
  ImGui::Begin(title.c_str(), nullptr, flags);
  for (std::size_t i = 0; i < task.steps.size(); ++i) {
    const TaskStepView& s = task.steps[i];
    const std::string head = std::to_string(i + 1) + ". " + s.name;
    switch (s.state) {
      case StepState::kDone: {
        char when[32];
        std::snprintf(when, sizeof when, "  done %.1f s", double(s.done_at));
        wrapped(kDoneColour, "[x] " + head + when);
        break;
      }
      case StepState::kActive: wrapped(kActiveColour, "[>] " + head); break;
      case StepState::kPending: wrapped(ImGui::GetStyle().Colors[ImGuiCol_TextDisabled], "[ ] " + head); break;
    }
    if (!s.detail.empty() && s.state != StepState::kPending) {
      ImGui::Indent();
      ImGui::TextWrapped("%s", s.detail.c_str());
      ImGui::Unindent();
    }
  }
  if (task.complete) wrapped(kDoneColour, "task complete");
  ImGui::Separator();
  std::size_t errors = 0;
  for (const TaskEventView& e : task.events) errors += e.error ? 1 : 0;
  ImGui::Text("%zu error%s", errors, errors == 1 ? "" : "s");
  const std::size_t first = task.events.size() > max_events ? task.events.size() - max_events : 0;
  for (std::size_t i = first; i < task.events.size(); ++i) {
    const TaskEventView& e = task.events[i];
    char when[32];
    std::snprintf(when, sizeof when, "%6.1f s  ", double(e.time));
    wrapped(e.error ? kErrorColour : ImGui::GetStyle().Colors[ImGuiCol_Text], when + e.text);
  }
  ImGui::End();
}

TaskPanelOverlay::TaskPanelOverlay() {
  ImGuiContext* previous = ImGui::GetCurrentContext();
  context_ = ImGui::CreateContext();
  ImGui::SetCurrentContext(context_);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.LogFilename = nullptr;
  ImGui::StyleColorsDark();
  const bool ok = ImGui_ImplOpenGL3_Init("#version 330");
  if (!ok) ImGui::DestroyContext(context_);
  ImGui::SetCurrentContext(previous);
  if (!ok) throw Error("task panel: Dear ImGui's OpenGL 3 backend did not start (its GL loader found no libGL.so.1)");
}

TaskPanelOverlay::~TaskPanelOverlay() {
  {
    CurrentContext current(context_);
    ImGui_ImplOpenGL3_Shutdown();
  }
  ImGui::DestroyContext(context_);
}

void TaskPanelOverlay::draw(const TaskView& task, int width, int height) {
  CurrentContext current(context_);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(float(width), float(height));
  io.DeltaTime = 1.0f / 30;  // no animation in the panel: any positive step will do
  const float panel = std::clamp(0.3f * float(width), 200.0f, 420.0f);
  const auto frame = [&] {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    draw_task_window(task, float(width) - panel - 8, 8, panel, true);
  };
  if (!laid_out_) {  // the layout frame: drawn nowhere
    frame();
    ImGui::EndFrame();
    laid_out_ = true;
  }
  frame();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace trocar
