#pragma once
/// The assessment report as one HTML page (docs/assessment.md, "The report"): the overall result
/// first, then the task, the GOALS summary, the metrics against the experts, plots of force, tip
/// paths, speed and errors over time, and the events. Inline CSS and SVG only (no script, no
/// network), so the page can be mailed or archived as one file; deterministic byte for byte.
#include <span>
#include <string>
#include <string_view>

#include "trocar/assessment/metrics.h"
#include "trocar/assessment/proficiency.h"
#include "trocar/assessment/trace.h"

namespace trocar {

/// A rendered frame shown beside an event on the timeline.
struct ReportFrame {
  Real time = 0;      ///< s, session time the frame shows
  std::string image;  ///< path or file name relative to the report
  std::string caption;
};

/// The HTML report a surgeon reads without help (docs/assessment.md, "The report"): one
/// self-contained page (inline CSS and SVG, no script, no network).
std::string assessment_html(const SessionTrace& trace, const Assessment& assessment, const MetricSettings& settings,
                            std::span<const ReportFrame> frames, const std::string& title);

/// Escapes & < > " ' for HTML text and attributes (defined with the shared page helpers, svg_plot.cpp).
std::string html_escape(std::string_view text);

}  // namespace trocar
