#pragma once
// Runs the trocar program as a user would (through the shell) for the CLI tests.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace trocar::test {

/// What a run of the program printed and returned.
struct RunResult {
  int exit_code = -1;   ///< the exit status, or -1 when it did not exit normally
  std::string output;   ///< stdout, with stderr appended unless stdout_only
};

/// Runs `program args` through the shell and collects its output and exit status.
inline RunResult run_program(const std::string& program, const std::string& args, bool stdout_only = false) {
  const std::string command = program + " " + args + (stdout_only ? " 2>/dev/null" : " 2>&1");
  RunResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) result.output.append(buffer, n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace trocar::test
