#include "trocar/procedure/procedure.h"

#include <cstdio>
#include <utility>

#include "trocar/core/error.h"

namespace trocar {
namespace {

/// printf into a std::string (events are rare: the one allocation update() may make).
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

std::size_t tissue_index(const World& world, const std::string& name, const char* key) {
  std::size_t index = 0;
  if (world.find_tissue(name, &index)) return index;
  throw Error(std::string("task.") + key + ": no tissue named \"" + name + "\"");
}

const Vec3& landmark(const std::map<std::string, Vec3>& landmarks, const std::string& name) {
  const auto it = landmarks.find(name);
  if (it == landmarks.end()) throw Error("task: the scene has no landmark \"" + name + "\"");
  return it->second;
}

}  // namespace

const char* to_string(TaskEventKind kind) {
  switch (kind) {
    case TaskEventKind::kStepDone: return "step done";
    case TaskEventKind::kTack: return "tack";
    case TaskEventKind::kTackInZone: return "tack in zone";
    case TaskEventKind::kTackNotHeld: return "tack not held";
    case TaskEventKind::kZoneForce: return "zone force";
    case TaskEventKind::kVesselGrasped: return "vessel grasped";
    case TaskEventKind::kMeshDropped: return "mesh dropped";
    case TaskEventKind::kZoneBurnt: return "zone burnt";
    case TaskEventKind::kBleeding: return "bleeding";
    case TaskEventKind::kHaemostasis: return "haemostasis";
    case TaskEventKind::kTackTornOut: return "tack torn out";
  }
  return "step done";
}

const char* Procedure::step_name(TaskStep s) {
  switch (s) {
    case TaskStep::kSacReduced: return "sac reduced";
    case TaskStep::kMeshPlaced: return "mesh placed";
    case TaskStep::kMeshFixed: return "mesh fixed";
  }
  return "";
}

Procedure::Procedure(TaskSpec spec, const World& world, std::span<const NamedZone> zones,
                     const std::map<std::string, Vec3>& landmarks)
    : spec_(std::move(spec)), zones_(zones.begin(), zones.end()) {
  sac_ = tissue_index(world, spec_.sac, "sac");
  mesh_ = tissue_index(world, spec_.mesh, "mesh");
  if (!spec_.wall_tissue.empty()) wall_tissue_ = tissue_index(world, spec_.wall_tissue, "wall_tissue");
  for (const std::string& v : spec_.vessels) vessels_.push_back(tissue_index(world, v, "vessels"));
  for (const auto& t : world.tissues) tissue_names_.push_back(t->name);
  for (const InstrumentBody& b : world.instruments) instrument_names_.push_back(b.name);

  wall_.point = landmark(landmarks, "wall_point");
  const Vec3 n = landmark(landmarks, "wall_normal");
  if (!(n.norm() > 0)) throw Error("task: landmark \"wall_normal\" must not be zero");
  wall_.normal = n.normalized();
  std::vector<Vec3> mpo;
  for (int k = 0;; ++k) {
    const auto it = landmarks.find("mpo_" + std::to_string(k));
    if (it == landmarks.end()) break;
    mpo.push_back(it->second);
  }
  if (!mpo.empty() && mpo.size() < 3) throw Error("task: the MPO needs at least 3 corners (landmarks mpo_0, mpo_1, mpo_2, ...)");
  coverage_ = CoverageRegion(wall_, mpo, landmark(landmarks, "defect_centre"), spec_.defect_radius + spec_.overlap,
                             spec_.coverage_spacing);
  for (const std::string& name : spec_.tack_landmarks) tack_landmarks_.push_back({name, landmark(landmarks, name)});

  TackerRules rules;
  rules.mesh_tissue = mesh_;
  rules.reach = spec_.tack_reach;
  rules.pullout_force = spec_.tack_pullout;
  tacker_rules_.assign(world.instruments.size(), rules);
  zone_episodes_.assign(world.instruments.size() * zones_.size(), {});
  zone_burnt_.assign(world.instruments.size() * zones_.size(), 0);
  vessel_held_.assign(world.instruments.size() * vessels_.size(), 0);
  const Vec3 g = world.tissues[mesh_]->settings.gravity;
  gravity_dir_ = g.norm() > 0 ? Vec3(g.normalized()) : Vec3::Zero();
  tacks_.reserve(64);
  events_.reserve(256);
  steps_[0].state = StepState::kActive;
}

void Procedure::set_tacker_tip(std::size_t instrument, const Vec3& tip_local, const Vec3& axis_local) {
  tacker_rules_.at(instrument).tip_local = tip_local;
  tacker_rules_.at(instrument).axis_local = axis_local;
}

std::size_t Procedure::error_count() const {
  std::size_t n = 0;
  for (const TaskEvent& e : events_) n += e.error ? 1 : 0;
  return n;
}

void Procedure::log(Real time, TaskEventKind kind, bool error, const Vec3& place, std::string zone, std::string text) {
  events_.push_back({time, kind, error, place, std::move(zone), std::move(text)});
}

void Procedure::update(const Simulation& sim) {
  watch_zones(sim);
  watch_vessels(sim);
  watch_mesh(sim);
  watch_burns(sim);
  watch_tacks(sim);
  evaluate(sim, TaskStep::kMeshFixed);  // cheap (a few tacks): its counts are shown before it is active
  for (std::size_t s = 0; s < kTaskSteps; ++s) {
    if (steps_[s].state == StepState::kDone) continue;
    steps_[s].state = StepState::kActive;
    if (evaluate(sim, static_cast<TaskStep>(s))) {
      steps_[s].state = StepState::kDone;
      steps_[s].done_at = sim.time();
      log(sim.time(), TaskEventKind::kStepDone, false, Vec3::Zero(), "",
          format("step %zu done: %s", s + 1, step_name(static_cast<TaskStep>(s))));
      if (s + 1 < kTaskSteps) steps_[s + 1].state = StepState::kActive;
    }
    break;  // only the first step not done is evaluated
  }
}

bool Procedure::evaluate(const Simulation& sim, TaskStep s) {
  const World& world = sim.world();
  switch (s) {
    case TaskStep::kSacReduced: {
      const TissueBody& sac = *world.tissues[sac_];
      measures_.sac_fraction = area_beyond_plane(sac.state.positions, sac.settings.triangles, wall_).fraction();
      return measures_.sac_fraction >= spec_.reduced_fraction;
    }
    case TaskStep::kMeshPlaced: {
      const TissueBody& mesh = *world.tissues[mesh_];
      measures_.coverage = coverage_.covered_fraction(mesh.state.positions, mesh.settings.triangles);
      measures_.fold_area = flipped_area(mesh.state.positions, mesh.settings.triangles, wall_.normal);
      return measures_.coverage >= 1.0 && measures_.fold_area <= spec_.max_fold_area;
    }
    case TaskStep::kMeshFixed: {
      const auto attachments = sim.attachments();
      const auto counts = [&](const TackRecord& r) {
        return r.outcome == TackOutcome::kFixed && r.zone.empty() && r.attachment < attachments.size() &&
               attachments[r.attachment].holding && (wall_tissue_ == kNoIndex || r.tissue == wall_tissue_);
      };
      int fixed = 0, in_zone = 0;
      for (const TackRecord& r : tacks_) {
        fixed += counts(r) ? 1 : 0;
        in_zone += r.zone.empty() ? 0 : 1;
      }
      int tacked = 0;
      for (const NamedPoint& l : tack_landmarks_)
        for (const TackRecord& r : tacks_)
          if (counts(r) && (r.tip - l.point).norm() <= spec_.tack_radius) {
            ++tacked;
            break;
          }
      measures_.fixed_tacks = fixed;
      measures_.landmarks_tacked = tacked;
      measures_.zone_tacks = in_zone;
      return fixed >= spec_.min_tacks && tacked == static_cast<int>(tack_landmarks_.size()) && in_zone == 0;
    }
  }
  return false;
}

void Procedure::watch_zones(const Simulation& sim) {
  if (zones_.empty()) return;
  const World& world = sim.world();
  const Real now = sim.time();
  const auto forces = sim.instrument_metrics();
  const std::size_t instruments = world.instruments.size();
  for (std::size_t i = 0; i < instruments; ++i) {
    const Vec3 tip = tacker_tip(world.instruments[i].instrument, tacker_rules_[i]).point;
    const Real force = i < forces.size() ? forces[i].force.norm() : 0;
    for (std::size_t z = 0; z < zones_.size(); ++z) {
      const NamedZone& zone = zones_[z];
      // Touching: the tip, or a point where the instrument touches a tissue or a rigid, in the zone.
      bool touch = zone.contains(tip);
      Vec3 place = tip;
      for (const Contact& c : sim.contacts()) {
        if (touch) break;
        if (c.object_a != i || (c.kind != ContactKind::kInstrumentTissue && c.kind != ContactKind::kInstrumentRigid))
          continue;
        const Vec3 mid = 0.5 * (c.segment_p + c.segment_q);
        if (zone.contains(mid)) touch = true, place = mid;
      }
      for (std::size_t t = 0; t < world.tissues.size() && !touch; ++t)
        for (const SolverContactPoint& p : sim.response(t).contact_points(i))
          if (zone.contains(p.point)) {
            touch = true;
            place = p.point;
            break;
          }
      ZoneEpisode& ep = zone_episodes_[i * zones_.size() + z];
      if (touch) {
        if (!ep.touching) ep = {true, false, now};
        ep.last_touch = now;
        if (!ep.reported && force > spec_.zone_force) {
          ep.reported = true;
          log(now, TaskEventKind::kZoneForce, true, place, zone.name,
              format("%s touched with %.2f N by %s (limit %.2f N)", zone.name.c_str(), force,
                     instrument_names_[i].c_str(), spec_.zone_force));
        }
      } else if (ep.touching && now - ep.last_touch >= spec_.zone_release) {
        ep.touching = false;
      }
    }
  }
}

void Procedure::watch_burns(const Simulation& sim) {
  const World& world = sim.world();
  const Real now = sim.time();
  // An electrode burning in a named zone: once per zone per press of its pedal.
  const auto vapour = sim.vapour();
  for (std::size_t i = 0; i < vapour.size() && i < world.instruments.size(); ++i) {
    if (!sim.energy_on(i)) std::fill_n(zone_burnt_.begin() + static_cast<std::ptrdiff_t>(i * zones_.size()),
                                       zones_.size(), std::uint8_t{0});
    if (!vapour[i].burning) continue;
    for (std::size_t z = 0; z < zones_.size(); ++z) {
      if (zone_burnt_[i * zones_.size() + z] || !zones_[z].contains(vapour[i].at)) continue;
      zone_burnt_[i * zones_.size() + z] = 1;
      log(now, TaskEventKind::kZoneBurnt, true, vapour[i].at, zones_[z].name,
          format("%s burnt by %s", zones_[z].name.c_str(), instrument_names_[i].c_str()));
    }
  }
  // A wound is an error; its haemostasis a note with the time it took.
  const Bleeding& bleeding = sim.bleeding();
  const auto wounds = bleeding.wounds();
  for (; wounds_seen_ < wounds.size(); ++wounds_seen_) {
    const Bleeding::Wound& w = wounds[wounds_seen_];
    const TissueBody& tissue = *world.tissues[sim.bleeding_tissue(w.tissue)];
    const Vec3 place = w.vertex < tissue.state.positions.size() ? tissue.state.positions[w.vertex] : Vec3::Zero();
    log(now, TaskEventKind::kBleeding, true, place, "",
        format("%s bleeding (%s, %.1f mm)", tissue.name.c_str(), w.vessel.artery ? "artery" : "vein",
               1e3 * w.vessel.diameter));
    wound_closed_.push_back(0);
  }
  for (std::size_t w = 0; w < wound_closed_.size(); ++w) {
    if (wound_closed_[w]) continue;
    const std::optional<Real> took = bleeding.time_to_haemostasis(w);
    if (!took) continue;
    wound_closed_[w] = 1;
    const TissueBody& tissue = *world.tissues[sim.bleeding_tissue(wounds[w].tissue)];
    log(now, TaskEventKind::kHaemostasis, false, Vec3::Zero(), "",
        format("%s: bleeding stopped (%s) after %.1f s, %.2f ml lost", tissue.name.c_str(),
               wounds[w].state == WoundState::kClipped ? "clipped" : "sealed", *took, 1e6 * wounds[w].emitted));
  }
}

void Procedure::watch_vessels(const Simulation& sim) {
  const World& world = sim.world();
  for (std::size_t i = 0; i < world.instruments.size(); ++i)
    for (std::size_t v = 0; v < vessels_.size(); ++v) {
      const bool held = sim.response(vessels_[v]).held_vertices(i) > 0;
      std::uint8_t& was = vessel_held_[i * vessels_.size() + v];
      if (held && !was) {
        const Vec3 tip = tacker_tip(world.instruments[i].instrument, tacker_rules_[i]).point;
        log(sim.time(), TaskEventKind::kVesselGrasped, true, tip, "",
            format("%s grasped by %s", tissue_names_[vessels_[v]].c_str(), instrument_names_[i].c_str()));
      }
      was = held ? 1 : 0;
    }
}

bool Procedure::mesh_has_holding_tack(const Simulation& sim) const {
  for (const AttachmentState& a : sim.attachments())
    if (a.holding && (a.spec.a.tissue == mesh_ || a.spec.b.tissue == mesh_)) return true;
  return false;
}

Vec3 Procedure::mesh_centroid(const Simulation& sim) const {
  const auto& x = sim.world().tissues[mesh_]->state.positions;
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : x) sum += p;
  return x.empty() ? sum : Vec3(sum / static_cast<Real>(x.size()));
}

void Procedure::watch_mesh(const Simulation& sim) {
  bool held = false;
  for (std::size_t i = 0; i < sim.world().instruments.size() && !held; ++i)
    held = sim.response(mesh_).held_vertices(i) > 0;
  if (held) {
    mesh_held_ = true;
    mesh_watch_ = false;
    return;
  }
  if (mesh_held_) {  // just let go of
    mesh_held_ = false;
    mesh_watch_ = !gravity_dir_.isZero();
    mesh_release_centroid_ = mesh_centroid(sim);
  }
  if (!mesh_watch_ || mesh_has_holding_tack(sim)) return;
  const Vec3 c = mesh_centroid(sim);
  const Real fall = (c - mesh_release_centroid_).dot(gravity_dir_);
  if (fall > spec_.drop_distance) {
    mesh_watch_ = false;
    log(sim.time(), TaskEventKind::kMeshDropped, true, c, "",
        format("mesh dropped: fell %.1f cm after it was let go of", 100 * fall));
  }
}

void Procedure::watch_tacks(const Simulation& sim) {
  const auto attachments = sim.attachments();
  for (std::size_t k = 0; k < tacks_.size(); ++k) {
    const TackRecord& r = tacks_[k];
    if (tack_let_go_[k] != 0 || r.attachment >= attachments.size() || attachments[r.attachment].holding) continue;
    tack_let_go_[k] = 1;
    const AttachmentState& a = attachments[r.attachment];
    const std::string from = r.tissue == kNoIndex ? std::string() : " of " + tissue_names_[r.tissue];
    const std::string why = a.stretched_out ? std::string(" (stretched beyond its length)")
                            : a.force > 0   ? format(" (%.1f N)", a.force)
                                            : std::string(" (its tissue cut away)");
    log(a.torn_at >= 0 ? a.torn_at : sim.time(), TaskEventKind::kTackTornOut, false, r.tip, r.zone,
        format("tack %zu torn out%s%s", k + 1, from.c_str(), why.c_str()));
  }
}

void Procedure::fire(Simulation& sim, std::size_t instrument) {
  if (instrument < sim.world().instruments.size() && sim.world().instruments[instrument].tool == "tacker")
    fire_tacker(sim, instrument);
}

const TackRecord& Procedure::fire_tacker(Simulation& sim, std::size_t instrument) {
  tacks_.push_back(trocar::fire_tacker(sim, instrument, tacker_rules_.at(instrument), zones_, tack_landmarks_));
  tack_let_go_.push_back(0);
  const TackRecord& r = tacks_.back();
  const std::string into = r.tissue == kNoIndex ? std::string() : " into " + tissue_names_[r.tissue];
  std::string near;
  if (r.landmark_distance >= 0) near = format(" (%.0f mm from %s)", 1000 * r.landmark_distance, r.landmark.c_str());
  log(r.time, TaskEventKind::kTack, false, r.tip, r.zone,
      format("tack %zu: %s%s%s", tacks_.size(), to_string(r.outcome), into.c_str(), near.c_str()));
  if (!r.zone.empty())
    log(r.time, TaskEventKind::kTackInZone, true, r.tip, r.zone,
        format("tack %zu in %s", tacks_.size(), r.zone.c_str()));
  if (r.outcome == TackOutcome::kFixed && r.attachment == kNoIndex)
    log(r.time, TaskEventKind::kTackNotHeld, true, r.tip, "",
        format("tack %zu through mesh and tissue not attached (attachment capacity full)", tacks_.size()));
  return r;
}

TaskView Procedure::view() const {
  TaskView v;
  v.title = spec_.name;
  for (std::size_t s = 0; s < kTaskSteps; ++s) {
    TaskStepView step;
    step.name = step_name(static_cast<TaskStep>(s));
    step.state = steps_[s].state;
    step.done_at = steps_[s].done_at;
    switch (static_cast<TaskStep>(s)) {
      case TaskStep::kSacReduced:
        step.detail = format("%.0f %% of the sac behind the wall (need %.0f %%)", 100 * measures_.sac_fraction,
                             100 * spec_.reduced_fraction);
        break;
      case TaskStep::kMeshPlaced:
        step.detail = format("covers %.0f %% of the MPO and %.1f cm round the defect; fold %.1f cm2 (max %.1f)",
                             100 * measures_.coverage, 100 * spec_.overlap, 1e4 * measures_.fold_area,
                             1e4 * spec_.max_fold_area);
        break;
      case TaskStep::kMeshFixed:
        step.detail = format("%d of %d tacks; %d of %zu landmarks; %d in zones", measures_.fixed_tacks,
                             spec_.min_tacks, measures_.landmarks_tacked, tack_landmarks_.size(),
                             measures_.zone_tacks);
        break;
    }
    v.steps.push_back(std::move(step));
  }
  for (const TaskEvent& e : events_) v.events.push_back({e.time, e.error, e.text});
  v.complete = complete();
  return v;
}

}  // namespace trocar
