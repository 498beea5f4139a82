// The session metrics and proficiency scoring on synthetic traces, against hand-computed values
// (docs/assessment.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "trocar/assessment/metrics.h"
#include "trocar/assessment/proficiency.h"

namespace trocar {
namespace {

constexpr Real kDt = 1e-3;
constexpr std::size_t kSamples = 2001;  // 0 … 2 s

/// Left hand: 10 cm along x at 5 cm/s over 2 s along its shaft (x). Right hand: 4 cm along y in
/// the first second (4 cm/s), still for the second, its shaft along z. A 2 N push on the
/// peritoneum for 0.3 s and a 5 N one on the abdominal wall for 0.2 s (below its 11.43 N); 20 N on
/// the prosthetic mesh.
SessionTrace two_hands() {
  SessionTrace t;
  t.scene = "synthetic";
  t.dt = kDt;
  InstrumentTrace left{"grasper_left", "grasper", "left", {}, {}, {}, {}, {}};
  InstrumentTrace right{"grasper_right", "grasper", "right", {}, {}, {}, {}, {}};
  TissueTrace peritoneum{"peritoneum", false, {}}, wall{"abdominal_wall", false, {}}, mesh{"mesh", true, {}};
  for (std::size_t k = 0; k < kSamples; ++k) {
    const Real s = static_cast<Real>(k) * kDt;
    t.time.push_back(s);
    left.tip.push_back(Vec3(0.05 * s, 0, 0));
    left.axis.push_back(Vec3::UnitX());
    right.tip.push_back(Vec3(0, 0.04 * std::min<Real>(s, 1), 0));
    right.axis.push_back(Vec3::UnitZ());
    for (InstrumentTrace* in : {&left, &right}) {
      in->present.push_back(1);
      in->in_view.push_back(k < 1500 ? 1 : 0);
    }
    const bool push = k >= 100 && k < 400, press = k >= 500 && k < 700;
    left.force.push_back(push ? 2 : 0);
    right.force.push_back(press ? 5 : 0);
    peritoneum.force.push_back(push ? 2 : 0);
    wall.force.push_back(press ? 5 : 0);
    mesh.force.push_back(push ? 20 : 0);  // the prosthetic mesh is not tissue: never counted
  }
  t.instruments = {left, right};
  t.tissues = {peritoneum, wall, mesh};
  t.events.push_back({0.25, "zone force", true, Vec3::Zero(), "triangle_of_doom", "touched"});
  t.events.push_back({0.5, "tack", false, Vec3::Zero(), "", "fixed"});
  t.task.present = true;
  t.task.steps = {{"sac reduced", 0.4}, {"mesh placed", 1.2}, {"mesh fixed", 1.9}};
  return t;
}

Real value(const std::vector<Metric>& m, const std::string& id) {
  const Metric* found = find_metric(m, id);
  EXPECT_NE(found, nullptr) << id;
  return found ? found->value : NAN;
}

TEST(Metrics, TwoHandsGiveTheirHandComputedValues) {
  const std::vector<Metric> m = measure(two_hands());
  EXPECT_NEAR(value(m, "task_time"), 1.9, 1e-12);  // the last step's completion
  EXPECT_NEAR(value(m, "path_length"), 0.14, 1e-9);
  EXPECT_NEAR(value(m, "grasper_left.path_length"), 0.10, 1e-9);
  EXPECT_NEAR(value(m, "depth_path"), 0.10, 1e-9);  // only the left moves along its shaft
  // Idle: no hand slower than 5 mm/s never happens (the left moves throughout).
  EXPECT_NEAR(value(m, "idle_time"), 0, 1e-12);
  EXPECT_NEAR(value(m, "grasper_right.idle_time"), 1.0, 2 * kDt);
  // Out of view: the last 501 samples of each hand.
  EXPECT_NEAR(value(m, "out_of_view_time"), 2 * 501 * kDt, 1e-9);
  // Bimanual: moving 1 s (right) vs 2 s (left); path 4 vs 10 cm.
  EXPECT_NEAR(value(m, "bimanual_moving_ratio"), 0.5, 2e-3);
  EXPECT_NEAR(value(m, "bimanual_path_ratio"), 0.4, 1e-9);
  // Tissue: 5 N max; mean while touching (300 × 2 N + 200 × 5 N)/500 = 3.2 N; above damage only the
  // peritoneum's 0.3 s (the wall's fascia takes 11.43 N).
  EXPECT_NEAR(value(m, "force_max"), 5, 1e-12);
  EXPECT_NEAR(value(m, "force_mean"), 3.2, 1e-12);
  EXPECT_NEAR(value(m, "time_above_damage"), 0.3, 1e-9);
  EXPECT_NEAR(value(m, "peritoneum.time_above_damage"), 0.3, 1e-9);
  EXPECT_NEAR(value(m, "abdominal_wall.time_above_damage"), 0, 1e-12);
  EXPECT_EQ(value(m, "zone_contacts"), 1);
  EXPECT_EQ(value(m, "errors"), 1);
  EXPECT_EQ(value(m, "steps_done"), 3);
  // Smoothness: constant speed has no jerk inside a movement; its LDLJ is finite (the ends' jumps).
  EXPECT_TRUE(std::isfinite(value(m, "smoothness")));
}

TEST(Metrics, TheSameTraceGivesTheSameValuesBitForBit) {
  const std::vector<Metric> a = measure(two_hands()), b = measure(two_hands());
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(std::memcmp(&a[i].value, &b[i].value, sizeof(Real)), 0) << a[i].id;
  }
}

TEST(Metrics, AnUnfinishedTaskTakesTheWholeSession) {
  SessionTrace t = two_hands();
  t.task.steps.back().done_at = -1;
  EXPECT_NEAR(value(measure(t), "task_time"), 2.0, 1e-12);
}

TEST(Metrics, ElectrosurgeryIsReportedInItsUnitsAndNotScored) {
  SessionTrace t = two_hands();
  EXPECT_EQ(find_metric(measure(t), "blood_loss"), nullptr);  // a scene that cannot burn or bleed
  t.energy.present = true;
  t.energy.energy = 12.5;
  t.energy.coagulated_area = 3e-5;    // 30 mm²
  t.energy.blood_loss = 2.5e-6;       // 2.5 ml
  t.energy.wounds = 2;
  t.energy.wounds_open = 1;
  t.energy.haemostasis_time = 4.0;
  t.events.push_back({1.0, "zone burnt", true, Vec3::Zero(), "triangle_of_doom", ""});
  t.events.push_back({1.5, "zone burnt", true, Vec3::Zero(), "triangle_of_pain", ""});
  const std::vector<Metric> m = measure(t);
  EXPECT_DOUBLE_EQ(value(m, "energy"), 12.5);
  EXPECT_NEAR(value(m, "coagulated_area"), 30.0, 1e-9);
  EXPECT_NEAR(value(m, "blood_loss"), 2.5, 1e-9);
  EXPECT_EQ(value(m, "zones_burnt"), 2.0);
  EXPECT_EQ(value(m, "wounds_open"), 1.0);
  EXPECT_EQ(value(m, "time_to_haemostasis"), 4.0);
  EXPECT_FALSE(find_metric(m, "blood_loss")->scored);
}

Metric scored(const std::string& id, Real v, bool lower_is_better = true, GoalsDomain d = GoalsDomain::kEfficiency) {
  return {id, id, "", d, lower_is_better, true, v};
}

TEST(Proficiency, ThePassMarkIsTheExpertMeanPlusTwoSD) {
  std::vector<std::vector<Metric>> experts;
  for (const Real v : {1.0, 2.0, 3.0, 4.0, 5.0})
    experts.push_back({scored("time", v), scored("ratio", 1 - v / 10, false, GoalsDomain::kBimanualDexterity)});
  const std::vector<ExpertStats> ref = expert_reference(experts);
  ASSERT_EQ(ref.size(), 2u);
  // mean 3, SD √2.5 (n − 1), best quartile the 25th percentile: 2.
  EXPECT_NEAR(ref[0].mean, 3, 1e-12);
  EXPECT_NEAR(ref[0].sd, std::sqrt(2.5), 1e-12);
  EXPECT_NEAR(ref[0].best_quartile, 2, 1e-12);
  // More is better: the 75th percentile, 0.8; the pass mark mean − 2 SD = 0.7 − 0.316.
  EXPECT_NEAR(ref[1].best_quartile, 0.8, 1e-12);
  const SessionTrace none;
  const Real limit = 3 + 2 * std::sqrt(2.5);
  {
    const Assessment a = assess(none, {scored("time", limit - 1e-9), scored("ratio", 0.39, false)}, ref);
    EXPECT_NEAR(a.metrics[0].limit, limit, 1e-12);
    EXPECT_TRUE(a.metrics[0].pass);
    EXPECT_TRUE(a.metrics[1].pass);  // 0.39 ≥ 0.7 − 2·0.158 = 0.384
    EXPECT_TRUE(a.pass);
  }
  {
    const Assessment a = assess(none, {scored("time", limit + 1e-9), scored("ratio", 0.38, false)}, ref);
    EXPECT_FALSE(a.metrics[0].pass);
    EXPECT_FALSE(a.metrics[1].pass);
    EXPECT_EQ(a.failed, 2);
    EXPECT_FALSE(a.pass);
  }
}

TEST(Proficiency, GoalsScoresMapTheDomainsMeanZ) {
  std::vector<std::vector<Metric>> experts;
  for (const Real v : {9.0, 11.0}) experts.push_back({scored("time", v)});  // mean 10, SD √2
  const std::vector<ExpertStats> ref = expert_reference(experts);
  const Real sd = std::sqrt(2.0);
  // z 0.4 → 5, 0.9 → 4, 1.9 → 3 (still passes), 3.9 → 2, 4.1 → 1; better than the mean → 5.
  const std::pair<Real, int> cases[] = {{0.4, 5}, {0.9, 4}, {1.9, 3}, {3.9, 2}, {4.1, 1}, {-3, 5}};
  for (const auto& [z, expected] : cases) {
    const Assessment a = assess(SessionTrace{}, {scored("time", 10 + z * sd)}, ref);
    const GoalsScore& g = a.goals[static_cast<std::size_t>(GoalsDomain::kEfficiency)];
    EXPECT_EQ(g.score, expected) << "z " << z;
    EXPECT_NEAR(g.mean_z, z, 1e-9);
    EXPECT_EQ(a.goals[0].score, 0);  // depth perception: no metric
  }
}

TEST(Proficiency, ASessionWhoseSimulationBlewUpIsNotAssessable) {
  SessionTrace t = two_hands();
  t.events.clear();
  const std::vector<Metric> m = measure(t);
  const std::vector<ExpertStats> ref = expert_reference({m, m});
  EXPECT_TRUE(assess(t, m, ref).pass);
  t.unstable_at = 1.5;
  const Assessment a = assess(t, m, ref);
  EXPECT_FALSE(a.assessable);
  EXPECT_FALSE(a.pass);
  EXPECT_EQ(a.failed, 0);  // not the trainee's metrics that failed
}

TEST(Proficiency, ErrorsOrAnUnfinishedTaskFailOverallWhateverTheMetrics) {
  SessionTrace t = two_hands();
  const std::vector<Metric> m = measure(t);
  std::vector<std::vector<Metric>> experts = {m, m};
  const std::vector<ExpertStats> ref = expert_reference(experts);
  Assessment a = assess(t, m, ref);
  EXPECT_EQ(a.failed, 0);  // every metric equal to the experts' (SD 0: the limit is the mean)
  EXPECT_EQ(a.errors, 1);
  EXPECT_FALSE(a.pass);
  t.events.erase(t.events.begin());
  EXPECT_TRUE(assess(t, m, ref).pass);
  t.task.steps[2].done_at = -1;
  a = assess(t, m, ref);
  EXPECT_FALSE(a.task_complete);
  EXPECT_FALSE(a.pass);
}

}  // namespace
}  // namespace trocar
