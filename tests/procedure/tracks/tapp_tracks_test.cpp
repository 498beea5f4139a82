// The hernia repair's scripted tracks (docs/procedure.md, "The expert and novice tracks"), played
// as `trocar run` plays them: the scene's keyframes, its fire and exchange events, the task
// evaluated after every step. The expert completes every step without an error; the novice makes
// exactly its known errors: the epigastric vessels grasped, a tack in the triangle of doom, and
// the mesh left short of the overlap (its step never completes).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "trocar/procedure/actions.h"
#include "trocar/procedure/procedure.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

const std::string kScenes = TROCAR_SCENES_DIR;

/// What playing a track showed.
struct Played {
  TaskView view;
  std::vector<TaskEvent> events;
  std::vector<TackRecord> tacks;
  std::size_t holding_tacks = 0;  ///< attachments still holding at the end
  Real max_kinetic = 0;           ///< J, the whole scene
  Real step_median_ms = 0;        ///< the whole step (StageTimings::step, µs → ms)
  bool stable = true;
  /// The farthest any tissue vertex within 1 cm of a shaft's axis lay beyond its port (m): outside
  /// the body, where nothing may carry it (docs/response.md, "The port").
  Real farthest_out = 0;
};

/// Of the tissue vertices within 1 cm of a shaft in the body, the farthest beyond its port (m).
Real farthest_beyond_a_port(const Simulation& sim) {
  Real out = 0;
  for (const InstrumentBody& body : sim.world().instruments) {
    const Instrument& tool = body.instrument;
    if (!tool.has_port() || (tool.pose().translation - tool.port()).norm() > 0.5) continue;  // parked
    const Vec3 axis = tool.pose().rotation * tool.local_shaft();
    for (const auto& tissue : sim.world().tissues)
      for (const Vec3& x : tissue->state.positions) {
        const Vec3 r = x - tool.port();
        const Real along = axis.dot(r);
        if (along > out && (r - along * axis).norm() < 0.01) out = along;
      }
  }
  return out;
}

Played play(const std::string& file) {
  Scene scene = load_scene(kScenes + "/" + file);
  scene.settings.measure_penetration = false;
  Simulation sim = make_simulation(scene);
  Procedure procedure(*scene.task, sim.world(), scene.zones, scene.landmarks);
  ActionScript actions(scene.actions);
  Played out;
  std::vector<double> step_times;
  const std::size_t steps = step_count(scene.duration, scene.timestep);
  step_times.reserve(steps);
  actions.play_before(sim.time() + scene.timestep,
                      [&](std::size_t i, std::uint32_t bit) { apply_actions(sim, i, bit, &procedure); });
  const DriveResult r = drive(sim, scene.timestep, steps, [&](const StepMetrics& m) {
    procedure.update(sim);
    out.max_kinetic = std::max(out.max_kinetic, m.kinetic_energy);
    step_times.push_back(m.timings.step);
    if (m.step_index % 10 == 0) out.farthest_out = std::max(out.farthest_out, farthest_beyond_a_port(sim));
    actions.play_before(sim.time() + scene.timestep,
                        [&](std::size_t i, std::uint32_t bit) { apply_actions(sim, i, bit, &procedure); });
  });
  out.stable = r.stable && r.steps == steps;
  out.view = procedure.view();
  out.events.assign(procedure.events().begin(), procedure.events().end());
  out.tacks.assign(procedure.tacks().begin(), procedure.tacks().end());
  for (const AttachmentState& a : sim.attachments()) out.holding_tacks += a.holding ? 1 : 0;
  std::nth_element(step_times.begin(), step_times.begin() + step_times.size() / 2, step_times.end());
  out.step_median_ms = step_times.empty() ? 0 : 1e-3 * step_times[step_times.size() / 2];
  std::printf("%s: %zu steps, stable %d, kinetic energy peak %.2g J, step median %.1f ms, tissue %.1f mm beyond a port\n",
              file.c_str(), r.steps, out.stable ? 1 : 0, out.max_kinetic, out.step_median_ms, 1e3 * out.farthest_out);
  for (const TaskStepView& s : out.view.steps)
    std::printf("  %-13s %-8s at %6.3f s  %s\n", s.name.c_str(), to_string(s.state), s.done_at, s.detail.c_str());
  for (const TaskEvent& e : out.events)
    std::printf("  %7.3f s %s%s\n", e.time, e.error ? "ERROR " : "", e.text.c_str());
  return out;
}

TEST(TappTracks, TheExpertCompletesEveryStepWithoutAnError) {
  const Played p = play("tapp_expert.json");
  ASSERT_TRUE(p.stable);
  ASSERT_EQ(p.view.steps.size(), kTaskSteps);
  for (const TaskStepView& s : p.view.steps) EXPECT_EQ(s.state, StepState::kDone) << s.name << ": " << s.detail;
  EXPECT_TRUE(p.view.complete);
  // In order: the sac before the mesh is placed, the mesh placed before it is fixed.
  EXPECT_LT(p.view.steps[0].done_at, p.view.steps[1].done_at);
  EXPECT_LT(p.view.steps[1].done_at, p.view.steps[2].done_at);
  for (const TaskEvent& e : p.events) EXPECT_FALSE(e.error) << e.time << " s: " << e.text;
  std::size_t fixed = 0;
  for (const TackRecord& t : p.tacks) {
    EXPECT_EQ(t.outcome, TackOutcome::kFixed) << "tack at " << t.time << " s";
    EXPECT_TRUE(t.zone.empty()) << t.zone;
    fixed += t.outcome == TackOutcome::kFixed ? 1 : 0;
  }
  EXPECT_GE(fixed, 4u);
  EXPECT_EQ(p.holding_tacks, fixed);  // every tack still holds at the end
  EXPECT_LT(p.max_kinetic, 0.05);     // no blow-up (they reach 1–7 J)
  // Nothing carried out along a shaft (without the ports, the sac's vertices 8–10 cm out).
  EXPECT_LT(p.farthest_out, 0.005);
}

TEST(TappTracks, TheNoviceMakesExactlyItsKnownErrors) {
  const Played p = play("tapp_novice.json");
  ASSERT_TRUE(p.stable);
  ASSERT_EQ(p.view.steps.size(), kTaskSteps);
  EXPECT_EQ(p.view.steps[0].state, StepState::kDone);                            // the sac is reduced
  EXPECT_NE(p.view.steps[1].state, StepState::kDone) << p.view.steps[1].detail;  // the mesh short of the overlap
  EXPECT_FALSE(p.view.complete);
  // Its known errors, and nothing else:
  //  - the epigastric vessels grasped by the left grasper on its way in (one event per vessel);
  //  - the tacker, brought to the triangle of doom through the contralateral (left) port, pressing
  //    the vessels it passes over (zone force, only before that tack);
  //  - that tack, in the triangle of doom.
  Real doom_tack = -1;
  for (const TaskEvent& e : p.events)
    if (e.kind == TaskEventKind::kTackInZone) doom_tack = e.time;
  std::size_t grasped = 0, pressed = 0, in_zone = 0, other = 0;
  for (const TaskEvent& e : p.events) {
    if (!e.error) continue;
    if (e.kind == TaskEventKind::kVesselGrasped && e.text.find("inferior_epigastric") != std::string::npos &&
        e.text.find("grasper_left") != std::string::npos) {
      ++grasped;
    } else if (e.kind == TaskEventKind::kTackInZone && e.zone == "triangle_of_doom") {
      ++in_zone;
    } else if (e.kind == TaskEventKind::kZoneForce && e.text.find("by tacker") != std::string::npos &&
               e.time <= doom_tack && e.time > doom_tack - 0.6 &&
               (e.zone == "epigastric_vessels" || e.zone == "triangle_of_doom" || e.zone == "iliac_vessels")) {
      ++pressed;
    } else {
      ++other;
      ADD_FAILURE() << "not a known error: " << e.time << " s " << e.text;
    }
  }
  EXPECT_GE(grasped, 1u);
  EXPECT_GE(pressed, 1u);
  EXPECT_EQ(in_zone, 1u);
  EXPECT_EQ(other, 0u);
  EXPECT_LT(p.max_kinetic, 0.05);
}

}  // namespace
}  // namespace trocar
