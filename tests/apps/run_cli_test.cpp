// `trocar run`: a small generated scene gives a valid report; a bad scene fails and writes nothing.
#include <gtest/gtest.h>

#include "support/run_program.h"
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

using trocar::test::RunResult;

RunResult run(const std::string& args) { return trocar::test::run_program(TROCAR_CLI, args); }

const char* kScene = R"({"schema": 1, "name": "probe-ball", "timestep": 0.001, "duration": 0.15, "gravity": [0, 0, 0],
 "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3},
   "material": {"preset": "liver"}, "fixed": {"below_plane": {"point": [0, 0, -0.015], "normal": [0, 0, 1]}}}],
 "instruments": [{"name": "probe", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},
   "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.04]}, {"t": 0.1, "position": [0, 0, 0.024]}]}}]})";

class RunCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("trocar_run_cli_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(RunCli, WritesAValidReportAndRecording) {
  std::ofstream(path("s.json")) << kScene;
  const RunResult r = run("run " + path("s.json") + " --report " + path("r.json") + " --record " + path("r.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(path("r.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["scene"], "probe-ball");
  EXPECT_EQ(j["steps"], 150);
  EXPECT_NEAR(j["sim_time_s"].get<double>(), 0.15, 1e-9);
  EXPECT_EQ(j["stable"], true);
  EXPECT_GT(j["contacts"]["pairs_total"].get<int>(), 0);
  EXPECT_GT(j["contacts"]["steps_with_contact"].get<int>(), 0);
  EXPECT_GT(j["instrument_force_N"]["max"].get<double>(), 0.0);
  for (const char* stage : {"broad_phase", "narrow_phase", "response", "deformation", "step"}) {
    const auto& t = j["timing_us"][stage];
    EXPECT_LE(t["median"].get<double>(), t["p99"].get<double>()) << stage;
    EXPECT_LE(t["p99"].get<double>(), t["max"].get<double>()) << stage;
  }
  EXPECT_GE(j["penetration_m"]["max"].get<double>(), j["penetration_m"]["p99"].get<double>());
  EXPECT_EQ(j["state_hash"].get<std::string>().size(), 16u);
  EXPECT_EQ(j["tunneling_events"].get<int>(), 0);  // a slow press: no vertex crosses the probe in a step
  // One header line and one line per step.
  std::ifstream csv(path("r.csv"));
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 151);

  // Same scene, same hash; --method and --duration are honoured.
  const RunResult again = run("run -q " + path("s.json") + " --report " + path("r2.json"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(again.output, "");
  std::ifstream in2(path("r2.json"));
  EXPECT_EQ(nlohmann::json::parse(in2)["state_hash"], j["state_hash"]);
  ASSERT_EQ(run("run -q " + path("s.json") + " --method normal --duration 0.05 --report " + path("r3.json")).exit_code, 0);
  std::ifstream in3(path("r3.json"));
  const auto j3 = nlohmann::json::parse(in3);
  EXPECT_EQ(j3["method"], "normal");
  EXPECT_EQ(j3["depth_cap"], true);  // the default (docs/response.md "Depth cap")
  EXPECT_EQ(j3["correction_speed"], 0.05);  // the default (docs/response.md "Gated correction")
  EXPECT_EQ(j3["steps"], 50);
}

TEST_F(RunCli, BadSceneFailsAndWritesNothing) {
  std::string text = kScene;
  text.replace(text.find("\"liver\""), 7, "\"basalt\"");
  std::ofstream(path("bad.json")) << text;
  const RunResult r = run("run " + path("bad.json") + " --report " + path("r.json") + " --record " + path("r.csv"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad.json: tissues[0].material.preset:"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("r.json")));
  EXPECT_FALSE(fs::exists(path("r.csv")));
  EXPECT_FALSE(fs::exists(path("r.csv.tmp")));
  const RunResult m = run("run " + path("bad.json") + " --method fastest");
  EXPECT_EQ(m.exit_code, 1);
}

}  // namespace
