#include "replay_command.h"

#include <cstdio>
#include <memory>
#include <string>

#include "trocar/runtime/session.h"
#include "trocar/sim/simulation.h"

namespace trocar::cli {
namespace {

struct ReplayOptions {
  std::string recording;
  bool quiet = false;
};

}  // namespace

void add_replay_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ReplayOptions>();
  CLI::App* cmd = app.add_subcommand("replay", "Redo a recorded real-time session in lock-step and check its state hash");
  cmd->add_option("recording", o->recording, "Session recording (trocar run --realtime --record)")->required();
  cmd->add_flag("--quiet,-q", o->quiet, "Print nothing but errors");
  cmd->callback([o, &exit_code]() {
    const ReplayResult r = replay_recording(o->recording);
    if (!o->quiet)
      std::printf("replay: %llu steps; state hash %s, recorded %s: %s\n", (unsigned long long)r.steps,
                  hash_hex(r.state_hash).c_str(), hash_hex(r.recorded_hash).c_str(), r.verdict().c_str());
    // 3: the state differs; 4: nothing to compare against (made on another kernel path).
    if (!r.comparable()) exit_code = 4;
    else if (!r.matches()) exit_code = 3;
  });
}

}  // namespace trocar::cli
