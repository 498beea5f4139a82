#include "task_report.h"

#include <cstdio>

namespace trocar::cli {

nlohmann::json task_report(const Procedure& procedure) {
  const TaskView view = procedure.view();
  nlohmann::json steps = nlohmann::json::array();
  for (const TaskStepView& s : view.steps)
    steps.push_back({{"name", s.name}, {"state", to_string(s.state)}, {"done_at_s", s.done_at}, {"detail", s.detail}});
  nlohmann::json tacks = nlohmann::json::array();
  for (const TackRecord& t : procedure.tacks())
    tacks.push_back({{"time_s", t.time},
                     {"instrument", t.instrument},
                     {"tip_m", {t.tip.x(), t.tip.y(), t.tip.z()}},
                     {"outcome", to_string(t.outcome)},
                     {"zone", t.zone},
                     {"landmark", t.landmark},
                     {"landmark_distance_m", t.landmark_distance}});
  nlohmann::json events = nlohmann::json::array();
  for (const TaskEvent& e : procedure.events())
    events.push_back({{"time_s", e.time},
                      {"kind", to_string(e.kind)},
                      {"error", e.error},
                      {"place_m", {e.place.x(), e.place.y(), e.place.z()}},
                      {"zone", e.zone},
                      {"text", e.text}});
  return {{"name", view.title}, {"complete", view.complete}, {"errors", procedure.error_count()},
          {"steps", steps},     {"tacks", tacks},            {"events", events}};
}

void print_task(const Procedure& procedure) {
  const TaskView view = procedure.view();
  std::printf("task %s: %s, %zu error%s\n", view.title.c_str(), view.complete ? "complete" : "not complete",
              procedure.error_count(), procedure.error_count() == 1 ? "" : "s");
  for (std::size_t i = 0; i < view.steps.size(); ++i) {
    const TaskStepView& s = view.steps[i];
    if (s.done_at >= 0)
      std::printf("  step %zu %s: done at %.3f s (%s)\n", i + 1, s.name.c_str(), s.done_at, s.detail.c_str());
    else
      std::printf("  step %zu %s: %s (%s)\n", i + 1, s.name.c_str(), to_string(s.state), s.detail.c_str());
  }
  for (const TaskEvent& e : procedure.events())
    std::printf("  %8.3f s  %s%s\n", e.time, e.error ? "ERROR " : "", e.text.c_str());
}

}  // namespace trocar::cli
