// Proficiency against expert sessions (docs/assessment.md, "Proficiency").
#include "trocar/assessment/proficiency.h"

#include <algorithm>
#include <cmath>

namespace trocar {
namespace {

/// The q-quantile (0…1) of sorted values, by linear interpolation between order statistics.
Real quantile(const std::vector<Real>& sorted, Real q) {
  if (sorted.empty()) return 0;
  const Real at = q * static_cast<Real>(sorted.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(at));
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (at - static_cast<Real>(i)) * (sorted[j] - sorted[i]);
}

/// GOALS-style 1–5 from a domain's mean z (worse positive): 5 within half an expert SD of the
/// experts' mean or better, 4 within 1 SD, 3 within 2 SD (the pass mark), 2 within 4 SD, else 1.
int goals_from_z(Real z) {
  if (z <= 0.5) return 5;
  if (z <= 1) return 4;
  if (z <= 2) return 3;
  if (z <= 4) return 2;
  return 1;
}

}  // namespace

Real pass_mark(const ExpertStats& e, bool lower_is_better) { return lower_is_better ? e.mean + 2 * e.sd : e.mean - 2 * e.sd; }

std::vector<ExpertStats> expert_reference(const std::vector<std::vector<Metric>>& sessions) {
  std::vector<ExpertStats> out;
  if (sessions.empty()) return out;
  for (const Metric& m : sessions.front()) {
    if (!m.scored) continue;
    std::vector<Real> values;
    for (const std::vector<Metric>& s : sessions)
      if (const Metric* found = find_metric(s, m.id)) values.push_back(found->value);
    ExpertStats e;
    e.id = m.id;
    e.sessions = values.size();
    Real sum = 0;
    for (const Real v : values) sum += v;
    e.mean = sum / static_cast<Real>(values.size());
    Real squares = 0;
    for (const Real v : values) squares += (v - e.mean) * (v - e.mean);
    e.sd = values.size() > 1 ? std::sqrt(squares / static_cast<Real>(values.size() - 1)) : 0;
    std::sort(values.begin(), values.end());
    e.best_quartile = quantile(values, m.lower_is_better ? 0.25 : 0.75);
    out.push_back(e);
  }
  return out;
}

Assessment assess(const SessionTrace& trace, const std::vector<Metric>& metrics,
                  const std::vector<ExpertStats>& reference) {
  Assessment a;
  Real z_sum[4] = {0, 0, 0, 0};
  int z_count[4] = {0, 0, 0, 0};
  for (const Metric& m : metrics) {
    MetricScore s;
    s.metric = m;
    const auto found = std::find_if(reference.begin(), reference.end(), [&](const ExpertStats& e) { return e.id == m.id; });
    if (m.scored && found != reference.end()) {
      s.has_reference = true;
      s.expert = *found;
      // A tie with an expert spread of 0 passes (the limit is the mean itself).
      s.limit = pass_mark(*found, m.lower_is_better);
      s.pass = meets(m.value, s.limit, m.lower_is_better);
      if (!s.pass) ++a.failed;
      const std::size_t d = static_cast<std::size_t>(m.domain);
      if (d < 4) {
        // z in expert SDs, worse positive; with no spread, a miss counts as far out (z = 10).
        const Real worse = m.lower_is_better ? m.value - found->mean : found->mean - m.value;
        const Real z = found->sd > 0 ? worse / found->sd : (worse > 0 ? 10 : 0);
        z_sum[d] += z;
        ++z_count[d];
      }
    }
    a.metrics.push_back(s);
  }
  for (std::size_t d = 0; d < 4; ++d) {
    GoalsScore g;
    g.domain = static_cast<GoalsDomain>(d);
    if (z_count[d] > 0) {
      g.mean_z = z_sum[d] / z_count[d];
      g.score = goals_from_z(g.mean_z);
    }
    a.goals.push_back(g);
  }
  for (const TraceEvent& e : trace.events) a.errors += e.error;
  a.task_complete = trace.task.complete();
  a.assessable = !(trace.unstable_at >= 0);
  a.pass = a.assessable && a.failed == 0 && a.errors == 0 && a.task_complete;
  return a;
}

}  // namespace trocar
