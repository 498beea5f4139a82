// `trocar study penetration --quick`: a tiny sweep writes the CSV, the summary and the plot
// script (plots only where gnuplot is installed). `trocar study robustness --quick`: one
// generated organ, press and a 1 m/s poke with sdf; the CSV, the markdown table and the plot
// script are written; bad arguments fail.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(StudyCli, QuickSweepWritesCsvAndSummary) {
  const fs::path out = fs::temp_directory_path() / ("trocar_study_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(TROCAR_CLI) + " study penetration --quick --scenes " + TROCAR_SCENES_DIR +
                          " --out " + out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string csv = read(out / "penetration.csv");
  std::istringstream lines(csv);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) ++n;
  EXPECT_EQ(n, 5);  // header + 1 scene × 1 speed × 2 methods × 2 periods
  EXPECT_EQ(csv.rfind("scene,method,period_ms,speed_m_s,steps,penetration_max_mm,penetration_p99_mm,", 0), 0u);
  EXPECT_NE(csv.find("probe_press_slide,obb,1,0.5,"), std::string::npos);
  EXPECT_NE(csv.find("probe_press_slide,primitive,5,0.5,"), std::string::npos);
  EXPECT_EQ(csv.find(",false"), std::string::npos);  // every run stable
  const std::string summary = read(out / "summary.md");
  EXPECT_NE(summary.find("# Penetration study"), std::string::npos);
  EXPECT_NE(summary.find("| obb | 1 |"), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(out / "plots.gp"));
  fs::remove_all(out);
}

TEST(StudyCli, MissingScenesFolderFails) {
  const std::string cmd = std::string(TROCAR_CLI) + " study penetration --quick --scenes /nonexistent --out " +
                          (fs::temp_directory_path() / "trocar_study_missing").string() + " > /dev/null 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0);
}

TEST(RobustnessCli, QuickSuiteWritesCsvTableAndPlotScript) {
  const fs::path out = fs::temp_directory_path() / ("trocar_robustness_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(TROCAR_CLI) + " study robustness --quick --out " + out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string csv = read(out / "robustness.csv");
  std::istringstream lines(csv);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) ++n;
  EXPECT_EQ(n, 3);  // header + 1 organ × 2 motions × 1 method
  EXPECT_EQ(csv.rfind("organ,source,vertices,triangles,motion,method,steps,step_median_us,", 0), 0u);
  EXPECT_NE(csv.find("lobe-2k-s1,generated,1002,2000,press,sdf,"), std::string::npos);
  EXPECT_NE(csv.find("lobe-2k-s1,generated,1002,2000,poke-1,sdf,"), std::string::npos);
  EXPECT_EQ(csv.find(",false"), std::string::npos);  // every run stable
  const std::string table = read(out / "robustness.md");
  EXPECT_NE(table.find("# Robustness suite"), std::string::npos);
  EXPECT_NE(table.find("## sdf: step budget met in "), std::string::npos);
  EXPECT_NE(table.find("| lobe-2k-s1 | 2000 | press |"), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(out / "plots.gp"));
  fs::remove_all(out);
}

TEST(RobustnessCli, UnknownMotionOrMissingFolderFails) {
  const std::string base = std::string(TROCAR_CLI) + " study robustness --out " +
                           (fs::temp_directory_path() / "trocar_robustness_bad").string();
  EXPECT_NE(std::system((base + " --motions wiggle --no-generated --organs /nonexistent > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --organs /nonexistent > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --methods magic > /dev/null 2>&1").c_str()), 0);
}

}  // namespace
