// trocar-bench: trocar measured against other libraries (FCL, Bullet). A program of its own so
// that the shipped `trocar` links none of them; `trocar bench ...` runs this program.
#include <CLI/CLI.hpp>
#include <iostream>

#include "collision_command.h"
#include "trocar/core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"trocar-bench: trocar measured against other libraries"};
  app.require_subcommand(1);
  int exit_code = 0;
  trocar::cli::add_collision_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const trocar::Error& e) {
    std::cerr << "trocar bench: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "trocar bench: internal error: " << e.what() << "\n";
    return 2;
  }
  return exit_code;
}
