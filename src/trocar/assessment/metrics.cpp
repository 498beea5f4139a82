// The trainee metrics of a session (docs/assessment.md).
#include "trocar/assessment/metrics.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "trocar/assessment/motion.h"

namespace trocar {
namespace {

/// An instrument without a `present` record is in the body throughout.
bool present_at(const InstrumentTrace& in, std::size_t k) { return in.present.empty() || in.present[k] != 0; }

/// The damage threshold of a tissue (N): the abdominal wall's fascia 11.43 N (Rodrigues et al.
/// 2012's highest), every other tissue the default (their lowest, 1.25 N).
Real damage_force_of(const std::string& tissue, const MetricSettings& s) {
  return tissue == "abdominal_wall" ? 11.43 : s.damage_force;
}

/// Movements: maximal runs of samples at or above the idle speed lasting ≥ 0.1 s. Smoothness is
/// their LDLJ weighted by duration (a whole session's jerk would grow with its length alone).
Real smoothness(const InstrumentTrace& in, std::span<const Real> speed, Real dt, const MetricSettings& s) {
  const std::size_t stride = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(1 / (s.jerk_rate_hz * dt))));
  const std::size_t shortest = static_cast<std::size_t>(std::ceil(0.1 / dt));
  Real weighted = 0, total = 0;
  std::size_t k = 0;
  while (k < speed.size()) {
    if (!(present_at(in, k) && speed[k] >= s.idle_speed)) {
      ++k;
      continue;
    }
    std::size_t end = k;
    while (end < speed.size() && present_at(in, end) && speed[end] >= s.idle_speed) ++end;
    if (end - k >= std::max(shortest, 6 * stride)) {
      const Real ldlj = log_dimensionless_jerk(std::span(in.tip).subspan(k, end - k), dt, stride);
      const Real duration = static_cast<Real>(end - k) * dt;
      weighted += ldlj * duration;
      total += duration;
    }
    k = end;
  }
  return total > 0 ? weighted / total : 0;
}

struct Hand {
  Real moving = 0, path = 0;
};

void add(std::vector<Metric>& out, std::string id, std::string name, std::string unit, GoalsDomain domain,
         bool lower_is_better, bool scored, Real value) {
  out.push_back({std::move(id), std::move(name), std::move(unit), domain, lower_is_better, scored, value});
}

Real ratio(Real a, Real b) {
  const Real hi = std::max(a, b);
  return hi > 0 ? std::min(a, b) / hi : 1;
}

}  // namespace

const char* to_string(GoalsDomain d) {
  switch (d) {
    case GoalsDomain::kDepthPerception: return "depth perception";
    case GoalsDomain::kBimanualDexterity: return "bimanual dexterity";
    case GoalsDomain::kEfficiency: return "efficiency";
    case GoalsDomain::kTissueHandling: return "tissue handling";
    case GoalsDomain::kNone: break;
  }
  return "";
}

std::vector<Metric> measure(const SessionTrace& trace, const MetricSettings& s) {
  using D = GoalsDomain;
  const Real dt = trace.dt;
  const std::size_t n = trace.samples();
  std::vector<Metric> out, details;

  // Motion, per instrument and in total.
  Real path = 0, depth = 0, out_of_view = 0, smooth_weighted = 0, smooth_path = 0;
  Hand left, right;
  std::vector<std::uint8_t> any_moving(n, 0), any_present(n, 0);
  std::vector<Real> speed(n);
  for (const InstrumentTrace& in : trace.instruments) {
    tip_speeds(in.tip, dt, speed, in.present);
    const Real p = path_length(in.tip, in.present);
    const Real d = depth_path(in.tip, in.axis, in.present);
    const Real idle = idle_time(speed, dt, s.idle_speed, in.present);
    const Real oov = out_of_view_time(in.present, in.in_view, dt);
    const Real sm = smoothness(in, speed, dt, s);
    Real moving = 0;
    for (std::size_t k = 0; k < n; ++k) {
      if (!present_at(in, k)) continue;
      any_present[k] = 1;
      if (speed[k] >= s.idle_speed) any_moving[k] = 1, moving += dt;
    }
    Hand& hand = in.hand == "left" ? left : right;
    hand.moving += moving;
    hand.path += p;
    path += p;
    depth += d;
    out_of_view += oov;
    if (p > 0) smooth_weighted += sm * p, smooth_path += p;
    const std::string pre = in.name + ".";
    add(details, pre + "path_length", in.name + ": path length", "m", D::kEfficiency, true, false, p);
    add(details, pre + "depth_path", in.name + ": path along the shaft", "m", D::kDepthPerception, true, false, d);
    add(details, pre + "idle_time", in.name + ": idle time", "s", D::kEfficiency, true, false, idle);
    add(details, pre + "smoothness", in.name + ": smoothness (log dimensionless jerk)", "", D::kEfficiency, false,
        false, sm);
    add(details, pre + "out_of_view_time", in.name + ": out of view", "s", D::kNone, true, false, oov);
  }
  Real idle = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (any_present[k] && !any_moving[k]) idle += dt;

  // Task time: to the last step's completion when the task is complete, else the whole session.
  Real task_time = n ? trace.time.back() : 0;
  if (trace.task.present && !trace.task.steps.empty() && trace.task.steps.back().done_at >= 0)
    task_time = trace.task.steps.back().done_at;

  // Tissue handling: a tissue's force while touched, above its damage threshold.
  Real force_max = 0, force_sum = 0, above = 0;
  std::size_t touched = 0;
  for (const TissueTrace& t : trace.tissues) {
    if (t.prosthetic) continue;
    const Real limit = damage_force_of(t.name, s);
    Real t_max = 0, t_above = 0;
    for (const Real f : t.force) {
      t_max = std::max(t_max, f);
      if (f > s.contact_force) force_sum += f, ++touched;
      if (f > limit) t_above += dt;
    }
    force_max = std::max(force_max, t_max);
    above += t_above;
    if (!(t_max > s.contact_force)) continue;  // never touched: nothing to report
    add(details, t.name + ".force_max", t.name + ": largest force", "N", D::kTissueHandling, true, false, t_max);
    add(details, t.name + ".time_above_damage", t.name + ": time above its damage threshold", "s",
        D::kTissueHandling, true, false, t_above);
  }
  int zone_contacts = 0, vessels_grasped = 0, errors = 0;
  for (const TraceEvent& e : trace.events) {
    zone_contacts += e.kind == "zone force";
    vessels_grasped += e.kind == "vessel grasped";
    errors += e.error;
  }

  add(out, "task_time", "Task time", "s", D::kEfficiency, true, true, task_time);
  add(out, "path_length", "Path length, all instruments", "m", D::kEfficiency, true, true, path);
  add(out, "idle_time", "Idle time (no instrument moving)", "s", D::kEfficiency, true, true, idle);
  add(out, "smoothness", "Smoothness (log dimensionless jerk)", "", D::kEfficiency, false, true,
      smooth_path > 0 ? smooth_weighted / smooth_path : 0);
  add(out, "depth_path", "Path along the shafts (depth perception)", "m", D::kDepthPerception, true, true, depth);
  add(out, "out_of_view_time", "Instrument out of view", "s", D::kNone, true, true, out_of_view);
  add(out, "bimanual_moving_ratio", "Moving time, weaker hand / stronger hand", "", D::kBimanualDexterity, false,
      true, ratio(left.moving, right.moving));
  add(out, "bimanual_path_ratio", "Path, weaker hand / stronger hand", "", D::kBimanualDexterity, false, true,
      ratio(left.path, right.path));
  add(out, "force_max", "Largest force on tissue", "N", D::kTissueHandling, true, true, force_max);
  add(out, "force_mean", "Mean force on tissue while touching", "N", D::kTissueHandling, true, true,
      touched ? force_sum / static_cast<Real>(touched) : 0);
  add(out, "time_above_damage", "Time above a tissue's damage threshold", "s", D::kTissueHandling, true, true, above);
  add(details, "errors", "Procedure errors", "", D::kNone, true, false, errors);
  add(details, "zone_contacts", "Named zones touched too hard", "", D::kTissueHandling, true, false, zone_contacts);
  add(details, "vessels_grasped", "Vessels grasped", "", D::kTissueHandling, true, false, vessels_grasped);
  if (trace.task.present) {
    int done = 0;
    for (const TraceStep& st : trace.task.steps) done += st.done_at >= 0;
    add(details, "steps_done", "Task steps completed", "", D::kNone, false, false, done);
    add(details, "tacks_fixed", "Tacks through mesh into tissue", "", D::kNone, false, false, trace.task.fixed_tacks);
    add(details, "tacks_in_zones", "Tacks in a named zone", "", D::kNone, true, false, trace.task.zone_tacks);
    add(details, "tacks_tissue_only", "Tacks into tissue only", "", D::kNone, true, false, trace.task.tissue_only_tacks);
    add(details, "mesh_coverage", "Mesh coverage of the required region", "%", D::kNone, false, false,
        100 * trace.task.coverage);
  }
  if (trace.energy.present) {
    // Details, not scored: an expert's session burns and bleeds so little that its spread would
    // make any burn a failure (docs/assessment.md, "Electrosurgery").
    const TraceEnergy& e = trace.energy;
    int burnt = 0;
    for (const TraceEvent& ev : trace.events) burnt += ev.kind == "zone burnt" ? 1 : 0;
    add(details, "energy", "Energy into tissue", "J", D::kTissueHandling, true, false, e.energy);
    add(details, "coagulated_area", "Tissue coagulated", "mm²", D::kTissueHandling, true, false, 1e6 * e.coagulated_area);
    add(details, "zones_burnt", "Named zones burnt", "", D::kTissueHandling, true, false, burnt);
    add(details, "blood_loss", "Blood loss", "ml", D::kTissueHandling, true, false, 1e6 * e.blood_loss);
    add(details, "wounds_open", "Wounds still bleeding at the end", "", D::kTissueHandling, true, false, e.wounds_open);
    add(details, "time_to_haemostasis", "Mean time to haemostasis", "s", D::kTissueHandling, true, false,
        e.haemostasis_time);
  }
  out.insert(out.end(), details.begin(), details.end());
  return out;
}

const Metric* find_metric(const std::vector<Metric>& metrics, const std::string& id) {
  for (const Metric& m : metrics)
    if (m.id == id) return &m;
  return nullptr;
}

}  // namespace trocar
