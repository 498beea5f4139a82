#pragma once
/// The trainee metrics of a session (docs/assessment.md): each with its unit, its GOALS domain and
/// whether less is better, computed from a SessionTrace alone.
#include <string>
#include <vector>

#include "trocar/assessment/trace.h"

namespace trocar {

/// GOALS domains (Vassiliou et al. 2005, Am J Surg 190:107) the metrics summarise into.
enum class GoalsDomain : std::uint8_t { kDepthPerception, kBimanualDexterity, kEfficiency, kTissueHandling, kNone };
/// "depth perception", "bimanual dexterity", "efficiency", "tissue handling", "".
const char* to_string(GoalsDomain d);

/// One metric of one session.
struct Metric {
  std::string id;                ///< stable key ("path_length", "grasper_right.path_length")
  std::string name;              ///< for people ("Path length, all instruments")
  std::string unit;              ///< "m", "s", "N", "", "%"
  GoalsDomain domain = GoalsDomain::kNone;
  bool lower_is_better = true;
  bool scored = true;            ///< compared with the experts (per-instrument details are not)
  Real value = 0;
};

/// What the metrics assume (docs/assessment.md gives each figure's source).
struct MetricSettings {
  Real idle_speed = 0.005;        ///< m/s: slower counts as idle (ours: below a deliberate slow move)
  Real jerk_rate_hz = 50;         ///< smoothness subsamples to this rate
  /// N: force above it counts as damaging (the lowest safe pull force over tissue types,
  /// 1.25 N, Rodrigues et al. 2012 — docs/assessment.md).
  Real damage_force = 1.25;
  Real contact_force = 0.05;      ///< N: an instrument "touches" a tissue above this
};

/// The metrics of `trace`, in a fixed order: totals first (scored), then per instrument and per
/// tissue (details). Deterministic: the same trace gives the same values bit for bit.
std::vector<Metric> measure(const SessionTrace& trace, const MetricSettings& settings = {});

/// The metric with `id`, or nullptr.
const Metric* find_metric(const std::vector<Metric>& metrics, const std::string& id);

}  // namespace trocar
