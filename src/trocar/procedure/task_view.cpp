#include "trocar/procedure/task_view.h"

namespace trocar {

const char* to_string(StepState state) {
  switch (state) {
    case StepState::kPending: return "pending";
    case StepState::kActive: return "active";
    case StepState::kDone: return "done";
  }
  return "pending";
}

}  // namespace trocar
