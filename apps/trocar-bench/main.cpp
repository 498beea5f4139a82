// trocar-bench: trocar measured against other libraries (FCL, Bullet). A program of its own so
// that the shipped `trocar` links none of them; `trocar bench ...` runs this program.
#include <CLI/CLI.hpp>

#include "cli_main.h"
#include "collision_command.h"

int main(int argc, char** argv) {
  CLI::App app{"trocar-bench: trocar measured against other libraries"};
  app.require_subcommand(1);
  int exit_code = 0;
  trocar::cli::add_collision_command(app, exit_code);
  return trocar::cli::run_main(app, argc, argv, exit_code, "trocar bench");
}
