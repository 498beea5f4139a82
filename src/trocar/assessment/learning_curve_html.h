#pragma once
/// A trainee's learning curve as one HTML page: each scored metric over the sessions against the
/// proficiency level (docs/assessment.md, "Learning curve"). Like the report (report_html.h), the
/// page is self-contained (inline CSS and SVG, no script, no network) and deterministic byte for
/// byte.
#include <span>
#include <string>
#include <vector>

#include "trocar/assessment/metrics.h"
#include "trocar/assessment/proficiency.h"

namespace trocar {

/// One attempt of a trainee (a session), in order.
struct Attempt {
  std::string label;            ///< e.g. the recording's file name
  std::vector<Metric> metrics;  ///< measure()'s metrics of the session
  bool pass = false;            ///< the session's overall result (Assessment::pass)
  int errors = 0;               ///< the procedure's errors (Assessment::errors)
};

/// A trainee's sessions against the proficiency level: first a table of the attempts (label,
/// overall pass/fail, errors, metrics failed) and one of the metrics (pass mark, latest value,
/// attempts to proficiency: the first attempt from which the metric stays passing); then, per
/// scored metric, its value against attempt number with the pass mark (expert mean ± 2 SD,
/// proficiency.h) and the experts' mean as lines, each attempt's point green where it passes and
/// red where it fails. A metric the experts lack shows its values only. No attempts: a page that
/// says so.
std::string learning_curve_html(std::span<const Attempt> attempts, const std::vector<ExpertStats>& reference,
                                const std::string& title);

}  // namespace trocar
