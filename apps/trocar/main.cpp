// trocar: the command-line program. Each subcommand lives in its own file.
#include <CLI/CLI.hpp>

#include "bench_command.h"
#include "cli_main.h"
#include "mesh_build_command.h"
#include "mesh_command.h"
#include "plot_command.h"
#include "replay_command.h"
#include "score_command.h"
#include "run_command.h"
#include "study_command.h"
#include "view_command.h"

int main(int argc, char** argv) {
  CLI::App app{"trocar: real-time simulation of laparoscopic instruments on deformable organs"};
  app.require_subcommand(1);
  int exit_code = 0;
  trocar::cli::install_scene_mesh_builder();  // scenes may name volumes to build (modelling module)
  trocar::cli::add_mesh_command(app, exit_code);
  trocar::cli::add_bench_command(app, exit_code);
  trocar::cli::add_run_command(app, exit_code);
  trocar::cli::add_study_command(app, exit_code);
  trocar::cli::add_replay_command(app, exit_code);
  trocar::cli::add_score_command(app, exit_code);
  trocar::cli::add_plot_command(app, exit_code);
  trocar::cli::add_view_command(app, exit_code);
  return trocar::cli::run_main(app, argc, argv, exit_code, "trocar");
}
