#pragma once
/// The assessment as JSON (beside the HTML report: the same numbers for a program), and the expert
/// reference file (docs/assessment.md, "Proficiency"). Deterministic: the same input gives the
/// same bytes.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trocar/assessment/proficiency.h"

namespace trocar {

/// The assessment's numbers: overall result, GOALS, every metric with its expert range, the task,
/// the events.
nlohmann::json assessment_json(const SessionTrace& trace, const Assessment& assessment);

/// An expert reference: each expert session's scored metrics and their statistics.
struct ExpertReference {
  std::vector<std::string> sessions;          ///< where each session came from
  std::vector<std::vector<Metric>> metrics;   ///< per session
  std::vector<ExpertStats> stats;             ///< expert_reference(metrics)
};
nlohmann::json reference_json(const ExpertReference& reference);
/// Reads a reference file; throws trocar::FileError naming the file and the key for a bad one.
ExpertReference read_reference(const std::filesystem::path& file);

}  // namespace trocar
