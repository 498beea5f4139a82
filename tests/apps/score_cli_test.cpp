// `trocar run --session` and `trocar score` (docs/assessment.md): a headless session recording
// replays bit for bit and scores to hand-computed numbers; the expert reference sets the pass
// mark; the shipped novice track's report carries exactly its errors; bad input is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/run_program.h"

namespace {

namespace fs = std::filesystem;

using trocar::test::RunResult;

RunResult trocar_cli(const std::string& args) { return trocar::test::run_program(TROCAR_CLI, args); }

/// A probe (tip at its keyframe position, 3 mm capsule) pressing a ball: down 16 mm in
/// `seconds`, through `via` (a detour, z) when given, then held, for 0.2 s in all.
std::string probe_ball(double seconds, double via = 0) {
  std::string keys = R"({"t": 0, "position": [0, 0, 0.04]})";
  if (via > 0) keys += R"(, {"t": )" + std::to_string(seconds / 2) + R"(, "position": [0, 0, )" + std::to_string(via) + "]}";
  keys += R"(, {"t": )" + std::to_string(seconds) + R"(, "position": [0, 0, 0.024]})";
  return R"({"schema": 1, "name": "probe-ball", "timestep": 0.001, "duration": 0.2, "gravity": [0, 0, 0],
 "tissues": [{"name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3},
   "material": {"preset": "liver"}, "fixed": {"below_plane": {"point": [0, 0, -0.015], "normal": [0, 0, 1]}}}],
 "instruments": [{"name": "probe", "port": "right", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},
   "motion": {"keyframes": [)" + keys + "]}}]}";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const nlohmann::json* metric(const nlohmann::json& report, const std::string& id) {
  for (const auto& m : report["metrics"])
    if (m["id"] == id) return &m;
  return nullptr;
}

class ScoreCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("trocar_score_cli_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path path(const std::string& name) const { return dir_ / name; }
  /// Writes the scene, runs it with --session; returns the recording's path.
  fs::path record(const std::string& name, const std::string& scene) {
    std::ofstream(path(name + ".json")) << scene;
    const RunResult r = trocar_cli("run -q " + path(name + ".json").string() + " --session " + path(name + ".trec").string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return path(name + ".trec");
  }
  /// Three expert presses (16 mm in 0.08, 0.1 and 0.12 s) recorded into experts/.
  void record_experts() {
    fs::create_directories(path("experts"));
    for (const double s : {0.08, 0.1, 0.12}) {
      const fs::path r = record("e" + std::to_string(static_cast<int>(s * 100)), probe_ball(s));
      fs::rename(r, path("experts") / r.filename());
    }
  }
  fs::path dir_;
};

TEST_F(ScoreCli, AHeadlessSessionReplaysBitForBitAndScoresToItsHandComputedPath) {
  const fs::path rec = record("press", probe_ball(0.1));
  const RunResult replay = trocar_cli("replay " + rec.string());
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_NE(replay.output.find("identical"), std::string::npos) << replay.output;

  const std::string scene = slurp(path("press.json"));
  const RunResult score = trocar_cli("score " + rec.string());
  ASSERT_EQ(score.exit_code, 0) << score.output;
  EXPECT_EQ(slurp(path("press.json")), scene) << "the scene beside the recording is left alone";
  const nlohmann::json j = nlohmann::json::parse(slurp(path("press.report.json")));
  // The tip goes 16 mm straight down along its shaft and stays: path and depth 16 mm.
  EXPECT_NEAR((*metric(j, "path_length"))["value"].get<double>(), 0.016, 1e-9);
  EXPECT_NEAR((*metric(j, "depth_path"))["value"].get<double>(), 0.016, 1e-9);
  EXPECT_NEAR((*metric(j, "task_time"))["value"].get<double>(), 0.2, 1e-9);  // no task: the session
  // Moving 0.1 s of 0.2 (down at 16 cm/s, then still): idle 0.1 s, give or take a sample.
  EXPECT_NEAR((*metric(j, "idle_time"))["value"].get<double>(), 0.1, 0.0025);
  EXPECT_GT((*metric(j, "force_max"))["value"].get<double>(), 0.1);  // the ball pushes back
  EXPECT_EQ(j["pass"], true);  // no reference, no task, no error
  const std::string html = slurp(path("press.report.html"));
  EXPECT_NE(html.find("PASS"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);

  // The same recording scores to the same bytes.
  ASSERT_EQ(trocar_cli("score -q " + rec.string() + " -o " + path("again.html").string()).exit_code, 0);
  EXPECT_EQ(slurp(path("press.report.json")), slurp(path("again.json")));
}

TEST_F(ScoreCli, TheExpertsSetThePassMarkAndADetourFailsIt) {
  record_experts();
  const RunResult ref = trocar_cli("score --expert " + path("experts").string() + " --write-reference " +
                                   path("ref.json").string());
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const nlohmann::json reference = nlohmann::json::parse(slurp(path("ref.json")));
  EXPECT_EQ(reference["sessions"].size(), 3u);
  for (const auto& m : reference["metrics"])
    if (m["id"] == "path_length") {
      EXPECT_NEAR(m["mean"].get<double>(), 0.016, 1e-9);
      EXPECT_NEAR(m["sd"].get<double>(), 0, 1e-9);
    }
  // Up 1 cm first, then down: 10 + 26 mm of path, above the experts' 16 mm.
  const fs::path trainee = record("detour", probe_ball(0.1, 0.05));
  ASSERT_EQ(trocar_cli("score -q " + trainee.string() + " --expert " + path("ref.json").string()).exit_code, 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(path("detour.report.json")));
  const nlohmann::json& path_length = *metric(j, "path_length");
  EXPECT_NEAR(path_length["value"].get<double>(), 0.036, 1e-9);
  EXPECT_EQ(path_length["pass"], false);
  EXPECT_EQ(j["pass"], false);
  // The expert folder itself gives the same scoring as the reference file written from it.
  ASSERT_EQ(trocar_cli("score -q " + trainee.string() + " --expert " + path("experts").string() + " -o " +
                       path("direct.html").string()).exit_code, 0);
  EXPECT_EQ(slurp(path("detour.report.json")), slurp(path("direct.json")));
}

TEST_F(ScoreCli, AttemptsInAFolderMakeALearningCurveAgainstTheExperts) {
  record_experts();
  // Three attempts, detours 20, 10 and 0 mm up first: the path passes only at the third.
  fs::create_directories(path("trainee"));
  const double via[] = {0.06, 0.05, 0};
  for (int k = 0; k < 3; ++k) {
    const fs::path r = record("attempt" + std::to_string(k + 1), probe_ball(0.1, via[k]));
    fs::rename(r, path("trainee") / r.filename());
  }
  const RunResult r = trocar_cli("score --history " + path("trainee").string() + " --expert " + path("experts").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("3 attempts, 1 passed overall"), std::string::npos) << r.output;
  const std::string html = slurp(path("trainee") / "learning_curve.html");
  for (const char* label : {"attempt1.trec", "attempt2.trec", "attempt3.trec"})
    EXPECT_NE(html.find(label), std::string::npos) << label;
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(trocar_cli("score --history " + path("nowhere").string()).exit_code, 0);
}

TEST_F(ScoreCli, ASessionWhoseSimulationBlewUpIsNotAssessedNorTakenAsAnExpert) {
  // Explicit Euler far beyond its stable step (k 10⁶ N/m on 1 g): it diverges within steps; the
  // run stops at the first unstable step and its recording ends there.
  const std::string diverging = R"({"schema": 1, "name": "diverging", "timestep": 0.001, "duration": 0.2, "gravity": [0, 0, -9.81],
   "tissues": [{"name": "sheet", "mesh": {"generate": "sheet", "width": 0.05, "height": 0.05, "nx": 4, "ny": 4},
     "material": {"mass": 0.001, "k_structural": 1000000, "k_bending": 1000, "damping": 0},
     "fixed": {"indices": [0]}, "integrator": "explicit-euler"}],
   "instruments": [{"name": "probe", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05},
     "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.05]}]}}]})";
  fs::create_directories(path("experts"));
  const fs::path blown = record("blown", diverging);
  const RunResult r = trocar_cli("score " + blown.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("NOT ASSESSABLE"), std::string::npos) << r.output;
  const nlohmann::json j = nlohmann::json::parse(slurp(path("blown.report.json")));
  EXPECT_EQ(j["assessable"], false);
  EXPECT_EQ(j["pass"], false);
  EXPECT_GT(j["unstable_at_s"].get<double>(), 0);
  EXPECT_NE(slurp(path("blown.report.html")).find("not assessable"), std::string::npos);
  // As the only expert session it leaves no reference: refused, saying why.
  fs::rename(blown, path("experts") / "blown.trec");
  const RunResult ref = trocar_cli("score --expert " + path("experts").string() + " --write-reference " +
                                   path("ref.json").string());
  EXPECT_NE(ref.exit_code, 0);
  EXPECT_NE(ref.output.find("blew up"), std::string::npos) << ref.output;
  EXPECT_FALSE(fs::exists(path("ref.json")));
}

TEST_F(ScoreCli, AnExpertSessionThatLeftItsTaskUndoneIsNotTakenAsAnExpert) {
  record_experts();
  // The same press in a scene that states the hernia repair (its sac and mesh out of reach): none
  // of its steps is done in 0.2 s.
  std::string with_task = probe_ball(0.1);
  with_task.insert(with_task.find("],\n \"instruments\""), R"(,
   {"name": "sac", "mesh": {"generate": "box", "size": [0.01, 0.01, 0.01]}, "translate": [0.3, 0, 0.01],
    "material": {"preset": "peritoneum"}},
   {"name": "mesh", "mesh": {"generate": "sheet", "width": 0.02, "height": 0.02, "nx": 2, "ny": 2},
    "translate": [0.3, 0.1, 0], "material": {"preset": "peritoneum"}})");
  with_task.insert(with_task.rfind('}'), R"(, "landmarks": {"wall_point": [0, 0, 0], "wall_normal": [0, 0, 1],
   "defect_centre": [0.3, 0, 0], "tack_cooper": [0, 0, 0], "tack_medial": [0, 0, 0], "tack_lateral": [0, 0, 0]},
   "task": {"sac": "sac", "mesh": "mesh"})");
  const fs::path undone = record("undone", with_task);
  ASSERT_TRUE(fs::exists(undone));
  fs::rename(undone, path("experts") / "undone.trec");
  const RunResult ref = trocar_cli("score --expert " + path("experts").string() + " --write-reference " +
                                   path("ref.json").string());
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  EXPECT_NE(ref.output.find("undone.trec left out: its task was not completed"), std::string::npos) << ref.output;
  EXPECT_EQ(nlohmann::json::parse(slurp(path("ref.json")))["sessions"].size(), 3u);
}

TEST_F(ScoreCli, BadInputIsRefusedWithAClearError) {
  const fs::path rec = record("press", probe_ball(0.1));
  std::string bytes = slurp(rec);
  std::ofstream(path("cut.trec"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  RunResult r = trocar_cli("score " + path("cut.trec").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("cut.trec"), std::string::npos) << r.output;
  r = trocar_cli("score " + rec.string() + " --expert " + path("nowhere").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("nowhere"), std::string::npos) << r.output;
  std::ofstream(path("bad.json")) << R"({"kind": "something else", "metrics": []})";
  r = trocar_cli("score " + rec.string() + " --expert " + path("bad.json").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("kind"), std::string::npos) << r.output;
  std::ofstream(path("bad2.json")) << R"({"kind": "trocar expert reference", "metrics": [{"id": "x", "mean": 1}]})";
  r = trocar_cli("score " + rec.string() + " --expert " + path("bad2.json").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("metrics[0].sd"), std::string::npos) << r.output;
  // --session records the scene as written: a --method override is refused.
  r = trocar_cli("run -q " + path("press.json").string() + " --method sdf --session " + path("m.trec").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("records the scene as written"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("m.trec")));
}

// The shipped novice track (scenes/tapp_novice.json) recorded and scored: the report carries
// exactly its known errors, the task is incomplete, the verdict FAIL (about a minute: the track
// is played, then replayed).
TEST_F(ScoreCli, TheNoviceTracksReportCarriesItsKnownErrors) {
  const fs::path rec = path("novice.trec");
  RunResult r = trocar_cli("run -q " + std::string(TROCAR_SCENES_DIR) + "/tapp_novice.json --session " + rec.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = trocar_cli("score -q " + rec.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(slurp(path("novice.report.json")));
  EXPECT_EQ(j["pass"], false);
  EXPECT_EQ(j["task_complete"], false);
  std::multiset<std::string> errors;
  for (const auto& e : j["events"])
    if (e["error"].get<bool>()) errors.insert(e["kind"].get<std::string>() + (e["zone"] == "" ? "" : " " + e["zone"].get<std::string>()));
  const std::multiset<std::string> expected = {"vessel grasped",          "zone force epigastric_vessels",
                                               "zone force triangle_of_doom", "zone force iliac_vessels",
                                               "tack in zone triangle_of_doom"};
  EXPECT_EQ(errors, expected);
  EXPECT_EQ((*metric(j, "vessels_grasped"))["value"].get<double>(), 1);
  EXPECT_EQ((*metric(j, "tacks_in_zones"))["value"].get<double>(), 1);
  const std::string html = slurp(path("novice.report.html"));
  EXPECT_NE(html.find("FAIL"), std::string::npos);
  EXPECT_NE(html.find("triangle_of_doom"), std::string::npos);
#ifdef TROCAR_HAVE_RENDER
  // A frame of the scope at each error, beside the report, shown on its timeline.
  for (int k = 1; k <= 5; ++k) {
    const std::string name = "novice.report_frames/error_0" + std::to_string(k) + ".png";
    EXPECT_TRUE(fs::exists(path(name))) << name;
    EXPECT_NE(html.find(name), std::string::npos) << name;
  }
  EXPECT_FALSE(fs::exists(path("novice.report_frames/error_06.png")));
#endif
}

}  // namespace
