#pragma once
// The top of every trocar program (trocar, trocar-bench): parse, run the subcommand's callback,
// and turn what it throws into an exit code: 1 for a user's error (trocar::Error), 2 for a bug.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <string>

#include "trocar/core/error.h"

namespace trocar::cli {

/// Parses argv into `app` (whose callbacks do the work) and returns the exit code: CLI11's for a
/// parse error, 1 after a trocar::Error, 2 after another exception, else `exit_code` as the
/// callbacks left it. Errors go to stderr prefixed with `program`.
inline int run_main(CLI::App& app, int argc, char** argv, const int& exit_code, const std::string& program) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const Error& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << program << ": internal error: " << e.what() << "\n";
    return 2;
  }
  return exit_code;
}

}  // namespace trocar::cli
