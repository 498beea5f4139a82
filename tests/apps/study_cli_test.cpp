// `trocar study penetration --quick`: a tiny sweep writes the CSV, the summary and the plot
// script (plots only where gnuplot is installed). `trocar study robustness --quick`: one
// generated organ × light-soft and heavy-stiff × the hook × press and a 1 m/s poke × xpbd and sdf;
// the CSV (with the solver, material, instrument, substeps, constraint error and energy columns),
// the markdown tables (summary per solver) and the plot script are written; the rest check writes
// its energy drift; bad arguments fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
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

/// The CSV's lines (header first).
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) out.push_back(line);
  return out;
}

/// The comma-separated fields of a line (empty fields kept).
std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream s(line);
  while (std::getline(s, field, ',')) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

/// Index of `name` in the header's fields (fails the test when absent).
std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  EXPECT_NE(it, header.end()) << name;
  return static_cast<std::size_t>(it - header.begin());
}

TEST(RobustnessCli, QuickSuiteWritesCsvTableAndPlotScript) {
  const fs::path out = fs::temp_directory_path() / ("trocar_robustness_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(TROCAR_CLI) + " study robustness --quick --out " + out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string csv = read(out / "robustness.csv");
  const std::vector<std::string> lines = lines_of(csv);
  // header + 1 organ × 2 materials × 1 instrument × 2 motions × 2 solvers
  ASSERT_EQ(lines.size(), 9u);
  EXPECT_EQ(csv.rfind("organ,source,vertices,triangles,material,instrument,motion,solver,integrator,steps,"
                      "step_median_us,",
                      0),
            0u);
  const std::vector<std::string> header = fields_of(lines[0]);
  for (const char* name : {"substeps_max", "cg_mean_contact", "constraint_error_max", "constraint_error_median",
                           "energy_drift", "energy_grew", "penetration_p99_mm", "stable"})
    column(header, name);
  for (const char* material : {"light-soft", "heavy-stiff"})
    for (const char* motion : {"press", "poke-1"})
      for (const char* solver : {"xpbd,xpbd", "sdf,implicit-euler"})
        EXPECT_NE(csv.find(std::string("lobe-2k-s1,generated,1002,2000,") + material + ",hook," + motion + "," +
                           solver + ","),
                  std::string::npos)
            << material << " " << motion << " " << solver;
  const std::size_t substeps = column(header, "substeps_max"), solver = column(header, "solver");
  const std::size_t cg = column(header, "cg_mean");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = fields_of(lines[i]);
    ASSERT_EQ(f.size(), header.size()) << lines[i];
    EXPECT_EQ(f.back(), "true") << lines[i];  // stable
    if (f[solver] == "xpbd")
      EXPECT_GE(std::stoi(f[substeps]), 1) << lines[i];
    else
      EXPECT_GT(std::stod(f[cg]), 0) << lines[i];
  }
  const std::string table = read(out / "robustness.md");
  EXPECT_NE(table.find("# Robustness suite"), std::string::npos);
  EXPECT_NE(table.find("## Summary"), std::string::npos);
  EXPECT_NE(table.find("| xpbd | xpbd | 4 | "), std::string::npos);
  EXPECT_NE(table.find("| sdf | implicit-euler | 4 | "), std::string::npos);
  EXPECT_NE(table.find("## xpbd: step budget met in "), std::string::npos);
  EXPECT_NE(table.find("## sdf: step budget met in "), std::string::npos);
  EXPECT_NE(table.find("| lobe-2k-s1 | 2000 | light-soft | hook | press |"), std::string::npos);
  EXPECT_NE(table.find("| lobe-2k-s1 | 2000 | heavy-stiff | hook | poke-1 |"), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(out / "plots.gp"));
  fs::remove_all(out);
}

TEST(RobustnessCli, RestCheckReportsEnergyDrift) {
  // The rest check with --quick's organ and solvers: light-stiff, no contact, 0.5 s.
  const fs::path out = fs::temp_directory_path() / ("trocar_robustness_rest_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd =
      std::string(TROCAR_CLI) + " study robustness --quick --motions rest --out " + out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::vector<std::string> lines = lines_of(read(out / "robustness.csv"));
  ASSERT_EQ(lines.size(), 3u);  // header + xpbd and sdf
  const std::vector<std::string> header = fields_of(lines[0]);
  const std::size_t motion = column(header, "motion"), material = column(header, "material");
  const std::size_t drift = column(header, "energy_drift"), grew = column(header, "energy_grew");
  const std::size_t contacts = column(header, "contact_steps"), steps = column(header, "steps");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = fields_of(lines[i]);
    ASSERT_EQ(f.size(), header.size()) << lines[i];
    EXPECT_EQ(f[motion], "rest");
    EXPECT_EQ(f[material], "light-stiff");
    EXPECT_EQ(f[steps], "500");
    EXPECT_EQ(f[contacts], "0");
    EXPECT_FALSE(f[drift].empty());
    EXPECT_TRUE(f[grew] == "0" || f[grew] == "1") << f[grew];
    EXPECT_EQ(f.back(), "true");
  }
  EXPECT_NE(read(out / "robustness.md").find("| rest |"), std::string::npos);
  fs::remove_all(out);
}

TEST(RobustnessCli, UnknownMotionOrMissingFolderFails) {
  const std::string base = std::string(TROCAR_CLI) + " study robustness --out " +
                           (fs::temp_directory_path() / "trocar_robustness_bad").string();
  EXPECT_NE(std::system((base + " --motions wiggle --no-generated --organs /nonexistent > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --organs /nonexistent > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --quick --methods magic > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --quick --solvers magic > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --quick --materials jelly > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + " --quick --instruments spoon > /dev/null 2>&1").c_str()), 0);
  fs::remove_all(fs::temp_directory_path() / "trocar_robustness_bad");
}

}  // namespace
