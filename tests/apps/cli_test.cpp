// Runs the trocar program as a user would and checks what it prints and returns.
#include <gtest/gtest.h>

#include "support/run_program.h"
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <nlohmann/json.hpp>
#include <string>

namespace {

namespace fs = std::filesystem;

using trocar::test::RunResult;

RunResult run(const std::string& args) { return trocar::test::run_program(TROCAR_CLI, args); }

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("trocar_cli_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(path(name)) << text; }

  fs::path dir_;
};

TEST_F(Cli, GenerateIcosphereThenInfoJson) {
  const RunResult gen = run("mesh generate icosphere --radius 0.05 --subdivisions 2 -o " + path("s.obj"));
  ASSERT_EQ(gen.exit_code, 0) << gen.output;
  EXPECT_NE(gen.output.find("162 vertices, 320 triangles"), std::string::npos) << gen.output;

  const RunResult info = run("mesh info --json " + path("s.obj"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const auto j = nlohmann::json::parse(info.output);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["format"], "obj");
  EXPECT_EQ(j[0]["vertices"], 162);   // 10·4² + 2
  EXPECT_EQ(j[0]["triangles"], 320);  // 20·4²
  EXPECT_EQ(j[0]["edges"], 480);      // 30·4²
  EXPECT_EQ(j[0]["closed"], true);
  EXPECT_EQ(j[0]["manifold"], true);
  EXPECT_EQ(j[0]["orientation"], "outward");
  EXPECT_EQ(j[0]["euler_characteristic"], 2);
  EXPECT_EQ(j[0]["defects"]["boundary_edges"], 0);
  // An inscribed polyhedron: a little under the sphere's volume (96.6 % at level 2).
  const double sphere = 4.0 / 3.0 * std::numbers::pi * std::pow(0.05, 3);
  const double volume = j[0]["volume"].get<double>();
  EXPECT_LT(volume, sphere);
  EXPECT_GT(volume, 0.95 * sphere);
  EXPECT_NEAR(j[0]["bounds"]["max"][2].get<double>(), 0.05, 1e-12);  // a vertex at the pole
}

TEST_F(Cli, SheetInfoTextShowsBoundaryEdges) {
  ASSERT_EQ(run("mesh generate sheet --width 0.4 --height 0.3 --nx 4 --ny 3 -q -o " + path("p.stl")).exit_code, 0);
  const RunResult info = run("mesh info " + path("p.stl"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("format                  stl"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("triangles               24"), std::string::npos) << info.output;       // 2·4·3
  EXPECT_NE(info.output.find("boundary edges          14"), std::string::npos) << info.output;  // 2(4+3)
  EXPECT_NE(info.output.find("closed                  no"), std::string::npos) << info.output;
}

TEST_F(Cli, RepairWeldsATriangleSoupIntoAClosedMesh) {
  // A unit tetrahedron written as a soup (every corner its own vertex) with one face inverted.
  write("soup.obj",
        "v 0 0 0\nv 0 1 0\nv 1 0 0\n"  // outward faces 1-3 (normals -z, -y, -x)
        "v 0 0 0\nv 1 0 0\nv 0 0 1\n"
        "v 0 0 0\nv 0 0 1\nv 0 1 0\n"
        "v 1 0 0\nv 0 1 0\nv 0 0 1\n"
        "f 1 2 3\nf 4 5 6\nf 7 8 9\nf 10 12 11\n");
  const RunResult before = run("mesh info --json " + path("soup.obj"));
  const auto jb = nlohmann::json::parse(before.output);
  EXPECT_EQ(jb[0]["vertices"], 12);
  EXPECT_EQ(jb[0]["defects"]["boundary_edges"], 12);
  EXPECT_EQ(jb[0]["defects"]["duplicate_vertices"], 8);  // 12 corners, 4 distinct points

  const RunResult rep = run("mesh repair " + path("soup.obj") + " " + path("fixed.obj"));
  ASSERT_EQ(rep.exit_code, 0) << rep.output;
  EXPECT_NE(rep.output.find("vertices   12 -> 4"), std::string::npos) << rep.output;

  const auto ja = nlohmann::json::parse(run("mesh info --json " + path("fixed.obj")).output);
  EXPECT_EQ(ja[0]["vertices"], 4);
  EXPECT_EQ(ja[0]["triangles"], 4);
  EXPECT_EQ(ja[0]["closed"], true);
  EXPECT_EQ(ja[0]["orientation"], "outward");
  EXPECT_NEAR(ja[0]["volume"].get<double>(), 1.0 / 6.0, 1e-12);
  EXPECT_EQ(ja[0]["defects"]["inconsistent_edges"], 0);
}

TEST_F(Cli, BadFilesNameTheFileAndPlaceAndExitNonZero) {
  write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  const RunResult bad = run("mesh info " + path("bad.obj"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find(path("bad.obj") + ":4:"), std::string::npos) << bad.output;

  const RunResult missing = run("mesh info " + path("nope.stl"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find(path("nope.stl")), std::string::npos) << missing.output;

  // One bad file does not stop the others; JSON carries the error per file.
  ASSERT_EQ(run("mesh generate box -q -o " + path("b.obj")).exit_code, 0);
  const RunResult both = run("mesh info --json " + path("nope.stl") + " " + path("b.obj"));
  EXPECT_EQ(both.exit_code, 1);
  const auto j = nlohmann::json::parse(both.output);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_TRUE(j[0].contains("error"));
  EXPECT_EQ(j[1]["triangles"], 12);

  const RunResult ext = run("mesh generate box -o " + path("b.xyz"));
  EXPECT_EQ(ext.exit_code, 1);
  EXPECT_NE(ext.output.find("b.xyz"), std::string::npos) << ext.output;
}

TEST_F(Cli, BadArgumentsAreRejected) {
  EXPECT_NE(run("").exit_code, 0);
  EXPECT_NE(run("mesh generate icosphere --radius -1 -o " + path("x.obj")).exit_code, 0);
  EXPECT_NE(run("mesh generate icosphere").exit_code, 0);  // -o is required
  EXPECT_NE(run("mesh frobnicate").exit_code, 0);
  EXPECT_FALSE(fs::exists(path("x.obj")));
}

}  // namespace
