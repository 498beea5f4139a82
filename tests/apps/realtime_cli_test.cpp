// `trocar run --realtime`, `trocar replay`, `trocar plot timing` and `trocar study multirate`
// from the command line: the report's haptic section, a replay that matches, a corrupt or
// truncated recording named with its byte offset, a coupling that breaks the passivity bound
// refused with its scene key.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/run_program.h"

namespace {

namespace fs = std::filesystem;
using trocar::test::RunResult;

RunResult run(const std::string& args) { return trocar::test::run_program(TROCAR_CLI, args); }

// A capsule presses a ball; the probe is driven in real time by its motion (scripted device).
std::string scene(const std::string& device = "") {
  return R"({"schema": 1, "name": "rt-ball", "timestep": 0.001, "duration": 0.6, "gravity": [0, 0, 0],
 "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3},
   "material": {"preset": "liver"}, "fixed": {"below_plane": {"point": [0, 0, -0.015], "normal": [0, 0, 1]}}}],
 "instruments": [{"name": "probe", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},)" +
         device + R"(
   "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.04]}, {"t": 0.3, "position": [0, 0, 0.024]}]}}]})";
}

class RealtimeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("trocar_rt_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(RealtimeCli, ReportHasTheHapticSectionAndTheRecordingReplays) {
  std::ofstream(path("s.json")) << scene();
  const RunResult r = run("run " + path("s.json") + " --realtime --report " + path("r.json") + " --record " +
                          path("s.trec") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(path("r.json"));
  const auto j = nlohmann::json::parse(in);
  const auto& h = j["haptic"];
  EXPECT_EQ(h["mode"], "multirate");
  // 0.6 s at 1 kHz is 600 periods: each one ticked or, after a stall, counted as skipped. (The
  // rate a machine reaches is bench_runtime's to measure, not a test's on a shared machine.)
  EXPECT_GT(h["ticks"].get<int>(), 0);
  EXPECT_EQ(h["ticks"].get<int>() + h["skipped_slots"].get<int>(), 600);
  EXPECT_GE(h["deadline_miss_fraction"].get<double>(), 0.0);
  EXPECT_LE(h["deadline_miss_fraction"].get<double>(), 1.0);
  EXPECT_GE(h["jitter_us_p99"].get<double>(), 0.0);
  EXPECT_GT(h["physics_steps"].get<int>(), 0);
  for (const char* m : {"haptic_tick", "broad_phase", "narrow_phase", "response", "deformation", "step"})
    EXPECT_GT(h["timing_us"][m]["count"].get<int>(), 0) << m;
  // The scripted device: one connection, never dropped, nothing malformed, a pose every tick.
  ASSERT_EQ(h["devices"].size(), 1u);
  EXPECT_EQ(h["devices"][0]["name"], "scripted");
  EXPECT_EQ(h["devices"][0]["poses_accepted"], h["ticks"]);
  EXPECT_EQ(h["devices"][0]["connections"], 1);
  EXPECT_EQ(h["devices"][0]["drops"], 0);
  EXPECT_EQ(h["devices"][0]["malformed"], 0);
  const RunResult rep = run("replay " + path("s.trec"));
  EXPECT_EQ(rep.exit_code, 0) << rep.output;
  EXPECT_NE(rep.output.find("identical"), std::string::npos) << rep.output;
  EXPECT_NE(rep.output.find(j["state_hash"].get<std::string>()), std::string::npos) << rep.output;
  // Every step the physics thread ran was recorded and replayed.
  EXPECT_NE(rep.output.find("replay: " + std::to_string(h["physics_steps"].get<int>()) + " steps"), std::string::npos)
      << rep.output;

  const RunResult plot = run("plot timing " + path("s.trec") + " --out " + path("plots"));
  ASSERT_EQ(plot.exit_code, 0) << plot.output;
  for (const char* f : {"physics_timing.svg", "physics_timing.png", "haptic_timing.svg", "haptic_timing.png"})
    EXPECT_GT(fs::file_size(dir_ / "plots" / f), 1000u) << f;
}

TEST_F(RealtimeCli, LockstepRunReplays) {
  std::ofstream(path("s.json")) << scene();
  const RunResult r = run("run " + path("s.json") + " --realtime --lockstep --duration 0.4 --record " +
                          path("s.trec") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResult rep = run("replay " + path("s.trec"));
  EXPECT_EQ(rep.exit_code, 0) << rep.output;
}

TEST_F(RealtimeCli, TruncatedRecordingIsAnErrorWithItsByteOffset) {
  std::ofstream(path("s.json")) << scene();
  ASSERT_EQ(run("run " + path("s.json") + " --realtime --duration 0.3 --record " + path("s.trec") + " -q").exit_code, 0);
  fs::resize_file(path("s.trec"), fs::file_size(path("s.trec")) - 10);
  const RunResult rep = run("replay " + path("s.trec"));
  EXPECT_EQ(rep.exit_code, 1);
  EXPECT_NE(rep.output.find(path("s.trec") + ": byte "), std::string::npos) << rep.output;
  // Plotting still works on the complete blocks, with a warning.
  const RunResult plot = run("plot timing " + path("s.trec") + " --out " + path("plots"));
  EXPECT_EQ(plot.exit_code, 0) << plot.output;
  EXPECT_NE(plot.output.find("ends early"), std::string::npos) << plot.output;
}

TEST_F(RealtimeCli, CouplingAboveThePassivityBoundIsRefused) {
  std::ofstream(path("s.json")) << scene(R"( "device": {"driver": "scripted", "coupling": {"stiffness": 5000}},)");
  const RunResult r = run("run " + path("s.json") + " --realtime --duration 0.1 -q");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("instruments[0].device.coupling"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("passivity"), std::string::npos) << r.output;
  // The same coupling is passive at 4 kHz (bound 12000 N/m).
  EXPECT_EQ(run("run " + path("s.json") + " --realtime --haptic-rate 4000 --duration 0.1 -q").exit_code, 0);
}

TEST_F(RealtimeCli, UnknownDriverNamesItsKey) {
  std::ofstream(path("s.json")) << scene(R"( "device": {"driver": "phantom"},)");
  const RunResult r = run("run " + path("s.json") + " --realtime --duration 0.1 -q");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("instruments[0].device.driver"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("unknown driver"), std::string::npos) << r.output;
}

/// The cells of a markdown table's row ("| a | b |" → {"a", "b"}).
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::size_t at = row.find('|');
  while (at != std::string::npos) {
    const std::size_t next = row.find('|', at + 1);
    if (next == std::string::npos) break;
    std::string cell = row.substr(at + 1, next - at - 1);
    cell.erase(0, cell.find_first_not_of(' '));
    cell.erase(cell.find_last_not_of(' ') + 1);
    out.push_back(cell);
    at = next;
  }
  return out;
}

TEST_F(RealtimeCli, MultirateStudyMatchesLockstep) {
  std::ofstream(path("s.json")) << scene();
  const RunResult r = run("study multirate " + path("s.json") + " --emulate --duration 0.6 --out " + path("mr"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The table: a header, a rule, then the emulation 1 and 2 ticks late.
  std::ifstream md(dir_ / "mr" / "multirate.md");
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(md, line);) rows.push_back(cells(line));
  ASSERT_EQ(rows.size(), 4u) << r.output;
  const auto number = [&](int row, int column) { return std::stod(rows[std::size_t(row)][std::size_t(column)]); };
  for (int row : {2, 3}) {
    ASSERT_EQ(rows[std::size_t(row)].size(), 9u);
    EXPECT_EQ(rows[std::size_t(row)][0], "s");
    EXPECT_EQ(number(row, 2), 600);   // 0.6 s at 1 kHz
    EXPECT_EQ(number(row, 3), 1000);  // physics every tick
    EXPECT_GT(number(row, 4), 1.0) << "the probe presses the ball: the reference's peak force (N)";
    // The multirate force matches the lock-step reference's: RMS error within 2 % of the peak,
    // new models arriving with no jump beyond physics' own largest (% of the device maximum),
    // and the emulation's physics saw exactly the reference's inputs.
    EXPECT_LT(number(row, 5), 2.0);
    EXPECT_GT(number(row, 5), 0.0);
    EXPECT_EQ(number(row, 6), 0.0);
    EXPECT_LE(number(row, 7), number(row, 8));
  }
  EXPECT_EQ(rows[2][1], "emulated, 1 tick late");
  EXPECT_EQ(rows[3][1], "emulated, 2 ticks late");
  EXPECT_EQ(number(2, 4), number(3, 4)) << "one reference for both";
  EXPECT_LT(number(2, 5), number(3, 5)) << "a model a tick later renders further from the reference";
  // The console says the same figure.
  char said[32];
  std::snprintf(said, sizeof said, "= %.2f %% of peak", number(2, 5));
  EXPECT_NE(r.output.find(said), std::string::npos) << said << "\n" << r.output;
}

}  // namespace
