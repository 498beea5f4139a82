// Runs `trocar bench collision` as a user would, on small meshes made with `trocar mesh generate`
// (`trocar bench` runs trocar-bench, built with TROCAR_BUILD_PEERS); and a `trocar` without
// trocar-bench beside it says what to build.
#include <gtest/gtest.h>

#include <cstdlib>

#include "support/run_program.h"
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace {

namespace fs = std::filesystem;

using trocar::test::RunResult;

/// Runs the program; stderr goes to the output too unless `stdout_only`.
RunResult run(const std::string& args, bool stdout_only = false) {
  return trocar::test::run_program(TROCAR_CLI, args, stdout_only);
}

class BenchCli : public ::testing::Test {
 protected:
  void SetUp() override {
    // FCL 0.7's BVHModel copy constructor allocates with malloc and its destructor frees with
    // delete[] (inside libfcl, not our code); in AddressSanitizer builds that mismatch would abort
    // the FCL peer, so the program under test is told not to report it. No effect otherwise.
    const std::string asan = std::getenv("ASAN_OPTIONS") ? std::getenv("ASAN_OPTIONS") : "";
    if (asan.find("alloc_dealloc_mismatch") == std::string::npos)
      setenv("ASAN_OPTIONS", (asan + (asan.empty() ? "" : ":") + "alloc_dealloc_mismatch=0").c_str(), 1);
    dir_ = fs::temp_directory_path() /
           ("trocar_bench_cli_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // A 1,280-triangle sphere of radius 5 cm and a 5 mm capsule (144 triangles) that cuts into it.
    ASSERT_EQ(run("mesh generate icosphere --radius 0.05 --subdivisions 3 -q -o " + path("tissue.obj")).exit_code, 0);
    ASSERT_EQ(run("mesh generate capsule --radius 0.005 --length 0.04 --segments 12 --rings 3 -q -o " +
                  path("tool.stl")).exit_code, 0);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

TEST_F(BenchCli, WithoutTrocarBenchSaysWhatToBuild) {
  // A copy of trocar alone in a folder: no trocar-bench beside it.
  const fs::path lone = dir_ / "lone" / "trocar";
  fs::create_directories(lone.parent_path());
  fs::copy_file(TROCAR_CLI, lone);
  const RunResult r = trocar::test::run_program(lone.string(), "bench collision --tissue " + path("tissue.obj") +
                                                                   " --tool " + path("tool.stl"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("trocar-bench"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("-DTROCAR_BUILD_PEERS=ON"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("libfcl-dev"), std::string::npos) << r.output;
}

#ifdef TROCAR_HAVE_BENCH_PROGRAM
TEST_F(BenchCli, JsonListsEveryMethodWithTheSamePairCount) {
  const RunResult r =
      run("bench collision --tissue " + path("tissue.obj") + " --tool " + path("tool.stl") + " --frames 5 --json", true);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j.is_array());
  ASSERT_GE(j.size(), 3u);  // ohc, bvh and brute at least; FCL and Bullet when compiled in
  std::set<std::string> methods;
  for (const auto& m : j) {
    ASSERT_TRUE(m.is_object());
    EXPECT_EQ(m.size(), 4u) << m.dump();
    ASSERT_TRUE(m["method"].is_string());
    ASSERT_TRUE(m["median_us"].is_number());
    ASSERT_TRUE(m["p95_us"].is_number());
    ASSERT_TRUE(m["pairs"].is_number_integer());
    EXPECT_GT(m["median_us"].get<double>(), 0) << "a query takes time";
    EXPECT_GE(m["p95_us"].get<double>(), m["median_us"].get<double>());
    EXPECT_EQ(m["pairs"], j[0]["pairs"]) << m["method"] << " vs " << j[0]["method"];
    methods.insert(m["method"].get<std::string>());
  }
  EXPECT_TRUE(methods.count("ohc") && methods.count("bvh") && methods.count("brute"));
  EXPECT_GT(j[0]["pairs"].get<int>(), 0);  // the tool does cut into the tissue
}

TEST_F(BenchCli, TextTableAndScales) {
  // The same scene in millimetres through the scale options: same pairs as in metres.
  const RunResult metres =
      run("bench collision --tissue " + path("tissue.obj") + " --tool " + path("tool.stl") + " --frames 3 --json", true);
  const RunResult mm = run("bench collision --tissue " + path("tissue.obj") + " --tool " + path("tool.stl") +
                               " --frames 3 --json --tissue-scale 1000 --tool-scale 1000",
                           true);
  ASSERT_EQ(metres.exit_code, 0) << metres.output;
  ASSERT_EQ(mm.exit_code, 0) << mm.output;
  EXPECT_EQ(nlohmann::json::parse(metres.output)[0]["pairs"], nlohmann::json::parse(mm.output)[0]["pairs"]);

  const RunResult text = run("bench collision --tissue " + path("tissue.obj") + " --tool " + path("tool.stl") + " --frames 3");
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("median_us"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("p95_us"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("\nohc "), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("\nbvh "), std::string::npos) << text.output;
}

TEST_F(BenchCli, MissingFileIsAnErrorNamingIt) {
  const RunResult r = run("bench collision --tissue " + path("nope.obj") + " --tool " + path("tool.stl") + " --frames 2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("nope.obj"), std::string::npos) << r.output;
}

TEST_F(BenchCli, BadAndEmptyMeshesAreErrorsNamingThem) {
  std::ofstream(path("bad.obj")) << "v 0 0 0\nf 1 2 zz\n";
  const RunResult bad = run("bench collision --tissue " + path("tissue.obj") + " --tool " + path("bad.obj"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("bad.obj"), std::string::npos) << bad.output;

  std::ofstream(path("empty.obj")) << "v 0 0 0\nv 1 0 0\n";
  const RunResult empty = run("bench collision --tissue " + path("empty.obj") + " --tool " + path("tool.stl"));
  EXPECT_NE(empty.exit_code, 0);
  EXPECT_NE(empty.output.find("empty.obj"), std::string::npos) << empty.output;
}

TEST_F(BenchCli, RequiresBothMeshes) {
  const RunResult r = run("bench collision --tissue " + path("tissue.obj"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--tool"), std::string::npos) << r.output;
}
#endif  // TROCAR_HAVE_BENCH_PROGRAM

}  // namespace
