// `trocar mesh phantom`, `trocar mesh labels` and `trocar mesh build` as a user runs them:
// outputs and the report; every bad input exits non-zero with the file and the reason and
// writes nothing. Without the modelling module the commands say how to get it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/run_program.h"

namespace {

namespace fs = std::filesystem;
using trocar::test::RunResult;

RunResult run(const std::string& args) { return trocar::test::run_program(TROCAR_CLI, args); }

class MeshBuildCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("trocar_mesh_build_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// True when the folder holds nothing but `allowed`.
  bool only(std::initializer_list<std::string> allowed) const {
    for (const auto& e : fs::directory_iterator(dir_)) {
      if (std::find(allowed.begin(), allowed.end(), e.path().filename().string()) == allowed.end()) return false;
    }
    return true;
  }
  fs::path dir_;
};

#if TROCAR_HAVE_MODELLING

TEST_F(MeshBuildCli, PhantomLabelsBuildReport) {
  ASSERT_EQ(run("mesh phantom torus --voxel 1 -o " + path("torus.nii.gz") + " --class-map " + path("torus.txt")).exit_code, 0);
  const RunResult labels = run("mesh labels " + path("torus.nii.gz"));
  ASSERT_EQ(labels.exit_code, 0) << labels.output;
  EXPECT_NE(labels.output.find("label    1"), std::string::npos) << labels.output;
  const RunResult b = run("mesh build " + path("torus.nii.gz") + " --label torus --class-map " + path("torus.txt") +
                          " --target-triangles 3000 -o " + path("torus.obj") + " --report " + path("build.json"));
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(b.output.find("genus 1, closed, manifold, outward"), std::string::npos) << b.output;
  for (const char* f : {"torus.obj", "torus.mtl", "torus.png", "build.json"}) EXPECT_TRUE(fs::is_regular_file(path(f))) << f;
  std::ifstream in(path("build.json"));
  const nlohmann::json r = nlohmann::json::parse(in);
  EXPECT_EQ(r.at("organ").get<std::string>(), "torus");
  EXPECT_LE(r.at("triangles").get<int>(), 3000);
  EXPECT_GE(r.at("triangles").get<int>(), 2700);
  EXPECT_EQ(r.at("genus").get<int>(), 1);
  EXPECT_LT(std::abs(r.at("volume_error_percent").get<double>()), 1.0);
  EXPECT_LT(r.at("hausdorff").at("max_voxels").get<double>(), 1.0);
  for (const char* stage : {"read", "components", "extract", "smooth", "decimate", "checks", "uv", "texture", "write"})
    EXPECT_GE(r.at("seconds").at(stage).get<double>(), 0.0) << stage;
  // The phantom's torus is centred on the world origin: its box is ±(25 + 9) mm across, ±9 mm high.
  EXPECT_NEAR(r.at("bounds_m").at("max")[0].get<double>(), 0.034, 1e-3);
  EXPECT_NEAR(r.at("bounds_m").at("min")[2].get<double>(), -0.009, 1e-3);
  // The written organ is clean by the project's own check.
  const RunResult info = run("mesh info " + path("torus.obj"));
  EXPECT_NE(info.output.find("defects                 none"), std::string::npos) << info.output;
  // VRML97 and STL too.
  ASSERT_EQ(run("mesh build " + path("torus.nii.gz") + " --label 1 -q -o " + path("torus.wrl")).exit_code, 0);
  EXPECT_NE(run("mesh info " + path("torus.wrl")).output.find("closed                  yes"), std::string::npos);
  ASSERT_EQ(run("mesh build " + path("torus.nii.gz") + " --label 1 -q --no-texture -o " + path("torus.stl")).exit_code, 0);
}

TEST_F(MeshBuildCli, ThresholdAGreyVolume) {
  ASSERT_EQ(run("mesh phantom sphere -o " + path("s.nrrd")).exit_code, 0);
  const RunResult b = run("mesh build " + path("s.nrrd") + " --threshold 0.5 -q -o " + path("s.obj"));
  EXPECT_EQ(b.exit_code, 0) << b.output;
  EXPECT_TRUE(fs::is_regular_file(path("s.obj")));
}

/// Each bad input: exit 1, the file and the reason on stderr, no output written.
TEST_F(MeshBuildCli, BadInputNamesFileAndReasonAndWritesNothing) {
  ASSERT_EQ(run("mesh phantom edge -o " + path("edge.nii.gz")).exit_code, 0);
  std::ofstream(path("junk.txt")) << "not a volume\n";
  {
    std::ifstream in(path("edge.nii.gz"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path("cut.nii.gz"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const struct {
    std::string args, says;
  } cases[] = {
      {path("missing.nii.gz") + " --label 1", "missing.nii.gz: no such file"},
      {path("junk.txt") + " --label 1", "junk.txt: unknown volume format"},
      {path("edge.nii.gz") + " --label 7", "label 7 is not in the volume (labels present: 1)"},
      {path("edge.nii.gz") + " --label liver", "no segment is named \"liver\""},
      {path("cut.nii.gz") + " --label 1", "cut.nii.gz: truncated gzip stream"},
      {path("edge.nii.gz"), "give --label"},
  };
  for (const auto& c : cases) {
    const RunResult r = run("mesh build " + c.args + " -o " + path("out.obj"));
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_TRUE(only({"edge.nii.gz", "junk.txt", "cut.nii.gz"})) << c.args;
  }
  const RunResult no_dir = run("mesh build " + path("edge.nii.gz") + " --label 1 -o " + path("nowhere/out.obj"));
  EXPECT_EQ(no_dir.exit_code, 1);
  EXPECT_NE(no_dir.output.find("its folder does not exist"), std::string::npos) << no_dir.output;
}

#else

TEST_F(MeshBuildCli, WithoutModellingSaysHowToGetIt) {
  // Every modelling command, with its options parsed (their targets must outlive the parse).
  for (const std::string& args : {"mesh build x.nii.gz --label 1 --threshold 1 2 -o " + path("x.obj"),
                                  std::string("mesh labels x.nii.gz"),
                                  "mesh phantom sphere --voxel 1 -o " + path("x.nii.gz")}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("built without the modelling module"), std::string::npos) << r.output;
    for (const char* package : {"libvtk9-dev", "libinsighttoolkit5-dev", "libcgal-dev"})
      EXPECT_NE(r.output.find(package), std::string::npos) << package << ": " << r.output;
  }
  EXPECT_TRUE(only({}));  // nothing written
}

#endif

}  // namespace
