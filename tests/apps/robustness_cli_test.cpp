// `trocar study robustness --quick`: one generated organ, press and a 1 m/s poke with sdf; the
// CSV, the markdown table and the plot script are written; bad arguments fail with a message.
#include <gtest/gtest.h>

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
