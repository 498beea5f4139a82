#pragma once
// `trocar score RECORDING`: the trainee's assessment of a session recording — metrics, proficiency
// against expert sessions, an HTML report and its JSON (docs/assessment.md).
#include <CLI/CLI.hpp>
#include <string>

namespace trocar::cli {

/// Scores `recording` against `expert` (a folder of recordings or a reference file; "" for none),
/// writes the HTML report to `output` ("" = RECORDING.report.html) and its JSON beside it (X.json for
/// X.html).
void score_session(const std::string& recording, const std::string& expert, const std::string& output, bool quiet);

/// Adds the `score` subcommand.
void add_score_command(CLI::App& app, int& exit_code);

}  // namespace trocar::cli
