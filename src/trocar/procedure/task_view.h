#pragma once
/// What a display shows of the task (the viewer's panel, the headless frames' overlay): each
/// step with its state and the errors so far. Plain data, copied out of the procedure after a
/// step by whoever steps.
#include <cstdint>
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// Where a step of the task stands.
enum class StepState : std::uint8_t { kPending, kActive, kDone };

/// "pending", "active", "done".
const char* to_string(StepState state);

/// One step as shown.
struct TaskStepView {
  std::string name;     ///< e.g. "sac reduced"
  StepState state = StepState::kPending;
  std::string detail;   ///< e.g. "92 % of the sac behind the wall", "3 of 4 tacks"
  Real done_at = -1;    ///< simulated time it completed (s), < 0 while not done
};

/// One error or notable event as shown.
struct TaskEventView {
  Real time = 0;        ///< s
  bool error = false;   ///< an error (red) rather than a note
  std::string text;     ///< e.g. "tack in triangle_of_doom"
};

/// The whole panel.
struct TaskView {
  std::string title;                   ///< the task's name
  std::vector<TaskStepView> steps;     ///< in order
  std::vector<TaskEventView> events;   ///< oldest first
  bool complete = false;               ///< every step done
};

}  // namespace trocar
