// trocar: the command-line program. Subcommands live in their own files (mesh_command.cpp, ...).
#include <CLI/CLI.hpp>
#include <iostream>

#include "trocar/core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"trocar: real-time simulation of laparoscopic instruments on deformable organs"};
  app.require_subcommand(1);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return 0;
}
