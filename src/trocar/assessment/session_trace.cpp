// A recording replayed into a SessionTrace (docs/assessment.md, "From a recording").
#include "trocar/assessment/session_trace.h"

#include <algorithm>

#include "trocar/core/stability.h"
#include "trocar/procedure/procedure.h"
#include "trocar/scene/camera.h"

namespace trocar {
namespace {

/// The monitor's aspect (the default frame, 1280 × 720): a tip outside it is out of view.
constexpr Real kViewAspect = 16.0 / 9.0;

/// "left" for an instrument whose port is named with "left" (the scenes' left and right ports),
/// else "right": the hands the bimanual metrics compare.
std::string hand_of(const InstrumentBody& body) {
  return body.port.find("left") != std::string::npos ? "left" : "right";
}

}  // namespace

void TraceSampler::start(const Scene& scene, const Simulation& sim, const Procedure* procedure) {
  const World& world = sim.world();
  trace_ = SessionTrace{};
  trace_.scene = scene.name;
  trace_.dt = scene.timestep;
  view_ = make_camera_view(scene.cameras.empty() ? default_camera(world) : scene.cameras.front(), kViewAspect);
  for (const InstrumentBody& body : world.instruments)
    trace_.instruments.push_back({body.name, body.tool, hand_of(body), {}, {}, {}, {}, {}});
  tissue_mass_ = 0;
  for (const auto& tissue : world.tissues) tissue_mass_ += tissue->settings.total_mass();
  for (std::size_t t = 0; t < world.tissues.size(); ++t)
    trace_.tissues.push_back({world.tissues[t]->name, procedure && t == procedure->mesh_tissue(), {}});
  sample(sim);  // the start, before the first step: the first step's motion counts
}

void TraceSampler::step(const Simulation& sim, const Procedure* /*procedure*/, const StepRecord& /*record*/) {
  sample(sim);
  const StepMetrics& m = sim.metrics();
  if (trace_.unstable_at < 0 && !is_stable(m.finite, m.kinetic_energy, tissue_mass_, m.tissue_rms_speed))
    trace_.unstable_at = sim.time();
}

void TraceSampler::sample(const Simulation& sim) {
  const World& world = sim.world();
  trace_.time.push_back(sim.time());
  const auto metrics = sim.instrument_metrics();
  for (std::size_t i = 0; i < trace_.instruments.size(); ++i) {
    InstrumentTrace& out = trace_.instruments[i];
    const Instrument& in = world.instruments[i].instrument;
    const Vec3 tip = in.pose().translation;
    Vec3 axis = in.top_world() - tip;  // the top vertex: the far end of the shaft (instrument.h)
    axis = axis.norm() > 0 ? Vec3(axis.normalized()) : Vec3::UnitZ();
    const Eigen::Vector3d on_screen = view_.project(tip, 1280, 720);
    const bool visible = on_screen.z() >= 0 && on_screen.z() <= 1 && on_screen.x() >= 0 && on_screen.x() <= 1280 &&
                         on_screen.y() >= 0 && on_screen.y() <= 720;
    out.tip.push_back(tip);
    out.axis.push_back(axis);
    out.force.push_back(i < metrics.size() ? metrics[i].force.norm() : 0);
    out.present.push_back(sim.parked(i) ? 0 : 1);
    out.in_view.push_back(visible ? 1 : 0);
  }
  // A tissue's load: the force its response put on each instrument (Simulation::tissue_force),
  // in magnitude, over the instruments (two pushing from both sides both load it).
  for (std::size_t t = 0; t < trace_.tissues.size(); ++t) {
    Real force = 0;
    for (std::size_t i = 0; i < trace_.instruments.size(); ++i) force += sim.tissue_force(t, i).norm();
    trace_.tissues[t].force.push_back(force);
  }
}

SessionTrace TraceSampler::finish(const Procedure* procedure, const Simulation* sim) {
  if (sim) {
    bool can = sim->bleeding().tissues() > 0;
    for (const InstrumentBody& body : sim->world().instruments) can = can || body.electrode.power > 0;
    TraceEnergy& e = trace_.energy;
    e.present = can;
    for (std::size_t t = 0; t < sim->world().tissues.size(); ++t) {
      const BurnTally b = sim->burn_tally(t);
      e.energy += b.energy;
      e.coagulated_area += b.coagulated_area;
      e.cut_area += b.cut_area;
    }
    const Bleeding& bleeding = sim->bleeding();
    e.blood_loss = bleeding.emitted();
    e.wounds = static_cast<int>(bleeding.wounds().size());
    Real took = 0;
    int closed = 0;
    for (std::size_t w = 0; w < bleeding.wounds().size(); ++w) {
      if (const std::optional<Real> t = bleeding.time_to_haemostasis(w)) {
        took += *t;
        ++closed;
      }
    }
    e.wounds_open = e.wounds - closed;
    e.haemostasis_time = closed > 0 ? took / closed : 0;
  }
  if (procedure) {
    for (const TaskEvent& e : procedure->events())
      trace_.events.push_back({e.time, to_string(e.kind), e.error, e.place, e.zone, e.text});
    TraceTask& task = trace_.task;
    task.present = true;
    for (std::size_t s = 0; s < kTaskSteps; ++s)
      task.steps.push_back({Procedure::step_name(static_cast<TaskStep>(s)), procedure->step(static_cast<TaskStep>(s)).done_at});
    for (const TackRecord& t : procedure->tacks()) {
      ++task.tacks;
      task.zone_tacks += !t.zone.empty();
      task.tissue_only_tacks += t.outcome == TackOutcome::kTissueOnly;
    }
    task.fixed_tacks = procedure->measures().fixed_tacks;
    task.coverage = procedure->measures().coverage;
    task.sac_fraction = procedure->measures().sac_fraction;
  }
  return std::move(trace_);
}

TracedSession trace_recording(const std::filesystem::path& recording, ReplayObserver* also) {
  // The procedure lives inside the replay: the task's outcome is read at its end.
  struct Sampler final : ReplayObserver {
    TraceSampler sampler;
    ReplayObserver* also = nullptr;
    SessionTrace finished;
    void start(const Scene& scene, const Simulation& sim, const Procedure* p) override {
      sampler.start(scene, sim, p);
      if (also) also->start(scene, sim, p);
    }
    void step(const Simulation& sim, const Procedure* p, const StepRecord& r) override {
      sampler.step(sim, p, r);
      if (also) also->step(sim, p, r);
    }
    void end(const Simulation& sim, const Procedure* p) override {
      finished = sampler.finish(p, &sim);
      if (also) also->end(sim, p);
    }
  } sampler;
  sampler.also = also;
  TracedSession out;
  out.replay = replay_recording(recording, &sampler);
  out.trace = std::move(sampler.finished);
  return out;
}

}  // namespace trocar
