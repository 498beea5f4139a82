#include "study_command.h"

#include "multirate_command.h"
#include "penetration_command.h"
#include "robustness_command.h"

namespace trocar::cli {

void add_study_command(CLI::App& app, int& exit_code) {
  (void)exit_code;
  CLI::App* study = app.add_subcommand("study", "Measure the simulator's claims");
  study->require_subcommand(1);
  add_penetration_command(*study);
  add_robustness_command(*study);
  add_multirate_command(*study);
}

}  // namespace trocar::cli
