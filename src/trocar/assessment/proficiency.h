#pragma once
/// Proficiency: a trainee's metrics against a reference set of expert sessions (docs/assessment.md,
/// "Proficiency"). The pass mark of a metric is the expert mean + 2 SD (− 2 SD where more is
/// better), as proficiency-based curricula set it from expert performance (Gallagher et al. 2005,
/// Ann Surg 241:364); the experts' best quartile is shown beside it (LAP Mentor's benchmarks).
#include <string>
#include <vector>

#include "trocar/assessment/metrics.h"

namespace trocar {

/// One metric's expert distribution.
struct ExpertStats {
  std::string id;
  Real mean = 0;
  Real sd = 0;              ///< sample standard deviation (n − 1)
  Real best_quartile = 0;   ///< the 25th percentile where less is better, the 75th where more is
  std::size_t sessions = 0;
};

/// A metric's pass mark: the expert mean + 2 SD, or − 2 SD where more is better.
Real pass_mark(const ExpertStats& expert, bool lower_is_better);
/// Whether `value` meets `mark` (a value on the mark passes).
inline bool meets(Real value, Real mark, bool lower_is_better) { return lower_is_better ? value <= mark : value >= mark; }

/// Per metric id, over the expert sessions' metrics (only `scored` ones). Deterministic.
std::vector<ExpertStats> expert_reference(const std::vector<std::vector<Metric>>& expert_sessions);

/// A metric scored against the experts.
struct MetricScore {
  Metric metric;
  bool has_reference = false;  ///< the experts have it (else no pass/fail)
  ExpertStats expert;
  Real limit = 0;              ///< the pass mark: mean ± 2 SD
  bool pass = true;
};

/// A GOALS-style domain score, 1 (poor) … 5 (expert), from the domain's metrics (docs/assessment.md
/// gives the mapping): each metric's z = (value − mean)/SD signed so that worse is positive; the
/// domain's mean z maps to 5 at z ≤ 0.5, 4 at ≤ 1, 3 at ≤ 2, 2 at ≤ 4, 1 above.
struct GoalsScore {
  GoalsDomain domain = GoalsDomain::kNone;
  int score = 0;               ///< 1…5 (0: no scored metric in the domain)
  Real mean_z = 0;
};

/// A session's assessment.
struct Assessment {
  std::vector<MetricScore> metrics;   ///< every metric, in measure()'s order
  std::vector<GoalsScore> goals;      ///< the four domains, in GoalsDomain order
  int failed = 0;                     ///< scored metrics below the pass mark
  int errors = 0;                     ///< the procedure's errors
  bool task_complete = false;         ///< every task step done (true when the scene has no task)
  bool assessable = true;             ///< the simulation stayed stable (SessionTrace::unstable_at < 0)
  /// Overall: every scored metric passes, no procedure error, the task complete; never for a
  /// session that cannot be assessed.
  bool pass = false;
};

/// Scores `metrics` of the session `trace` against `reference` (may be empty: nothing scored,
/// the overall result then rests on errors and the task).
Assessment assess(const SessionTrace& trace, const std::vector<Metric>& metrics,
                  const std::vector<ExpertStats>& reference);

}  // namespace trocar
