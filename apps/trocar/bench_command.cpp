#include "bench_command.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "trocar/core/error.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

/// trocar-bench beside the running program (the build's bin/ or the install's bin/).
fs::path bench_program() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path("trocar-bench") : self.parent_path() / "trocar-bench";
}

[[noreturn]] void run_bench(const std::vector<std::string>& args) {
  const fs::path program = bench_program();
  std::error_code ec;
  if (!fs::is_regular_file(program, ec))
    throw Error("`trocar bench` runs the trocar-bench program, which this build did not make (" + program.string() +
                " is missing). Build it: configure with -DTROCAR_BUILD_PEERS=ON and build the target trocar_bench; "
                "FCL (apt install libfcl-dev) and Bullet (apt install libbullet-dev) are compared when installed");
  std::vector<std::string> words = {program.string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  ::execv(program.c_str(), argv.data());
  throw Error(program.string() + ": cannot run: " + std::strerror(errno));
}

}  // namespace

void add_bench_command(CLI::App& app, int& /*exit_code*/) {
  CLI::App* bench = app.add_subcommand(
      "bench", "Measure trocar against other libraries (runs trocar-bench; `trocar bench --help` lists its measures)");
  bench->prefix_command();  // everything after `bench` is trocar-bench's
  bench->set_help_flag();   // --help too
  bench->callback([bench] { run_bench(bench->remaining()); });
}

}  // namespace trocar::cli
