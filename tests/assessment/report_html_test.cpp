// The HTML assessment report on a synthetic session (no assess(): the assessment is filled by
// hand, so each check knows what the page must say): the overall result first, escaping, the
// damage threshold where the axis puts 1.25 N, thinned polylines, byte-for-byte determinism.
#include "trocar/assessment/report_html.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

namespace trocar {
namespace {

constexpr const char* kScriptTissue = "peritoneum <script>alert(1)</script>";

/// 2000 samples at 1 ms: a grasper circling, a tacker sliding in after 0.3 s, two loaded tissues
/// (one spiking over the damage threshold), an error, a note and a three-step task, one undone.
SessionTrace synthetic_trace() {
  SessionTrace t;
  t.scene = "tapp_hernia";
  t.dt = 0.001;
  const std::size_t n = 2000;
  InstrumentTrace grasper, tacker;
  grasper.name = "grasper_right", grasper.tool = "grasper", grasper.hand = "right";
  tacker.name = "tacker_left", tacker.tool = "tacker", tacker.hand = "left";
  TissueTrace peritoneum{.name = kScriptTissue, .force = {}};
  TissueTrace mesh{.name = "mesh", .force = {}};
  for (std::size_t i = 0; i < n; ++i) {
    const Real time = static_cast<Real>(i + 1) * t.dt;
    t.time.push_back(time);
    grasper.tip.push_back(Vec3(0.03 * std::cos(4 * time), 0.03 * std::sin(4 * time), 0.1 + 0.01 * time));
    tacker.tip.push_back(Vec3(-0.05 + 0.02 * time, 0.01, 0.12 - 0.01 * time));
    for (InstrumentTrace* inst : {&grasper, &tacker}) {
      inst->axis.push_back(Vec3::UnitZ());
      inst->force.push_back(0);
      inst->in_view.push_back(1);
    }
    grasper.present.push_back(1);
    tacker.present.push_back(i >= 300 ? 1 : 0);
    peritoneum.force.push_back(0.4 + 0.3 * std::sin(10 * time) + (i == 800 ? 1.2 : 0));  // one 1 ms spike
    mesh.force.push_back(i > 1000 ? 0.2 : 0);
  }
  t.instruments = {grasper, tacker};
  t.tissues = {peritoneum, mesh};
  t.events.push_back({.time = 0.8,
                      .kind = "zone force",
                      .error = true,
                      .place = Vec3::Zero(),
                      .zone = "triangle of doom",
                      .text = "1.6 N in the triangle of doom"});
  t.events.push_back(
      {.time = 1.5, .kind = "tack", .error = false, .place = Vec3::Zero(), .zone = "", .text = "tack fixed the mesh"});
  t.task.present = true;
  t.task.steps = {{"flap dissected", 0.5}, {"mesh placed", 1.2}, {"mesh fixed", -1}};
  t.task.tacks = 4;
  t.task.fixed_tacks = 3;
  t.task.zone_tacks = 1;
  t.task.tissue_only_tacks = 1;
  t.task.coverage = 0.82;
  return t;
}

MetricScore scored(const std::string& id, const std::string& name, const std::string& unit, Real value, Real mean,
                   Real sd, bool pass) {
  MetricScore m;
  m.metric = Metric{.id = id,
                    .name = name,
                    .unit = unit,
                    .domain = GoalsDomain::kEfficiency,
                    .lower_is_better = true,
                    .scored = true,
                    .value = value};
  m.has_reference = true;
  m.expert = ExpertStats{.id = id, .mean = mean, .sd = sd, .best_quartile = mean - 0.5 * sd, .sessions = 12};
  m.limit = mean + 2 * sd;
  m.pass = pass;
  return m;
}

/// One failing metric (time), two passing, one per-instrument detail; one error; task undone.
Assessment failing_assessment() {
  Assessment a;
  a.metrics.push_back(scored("time", "Task time", "s", 2.0, 1.5, 0.2, false));
  a.metrics.push_back(scored("path_length", "Path length, all instruments", "m", 0.35, 0.3, 0.05, true));
  a.metrics.push_back(scored("max_force", "Maximum force on tissue", "N", 1.1, 0.9, 0.2, true));
  MetricScore detail;
  detail.metric = Metric{.id = "grasper_right.path_length",
                         .name = "grasper_right path length",
                         .unit = "m",
                         .domain = GoalsDomain::kNone,
                         .lower_is_better = true,
                         .scored = false,
                         .value = 0.012};
  a.metrics.push_back(detail);
  a.goals = {{GoalsDomain::kDepthPerception, 4, 0.8},
             {GoalsDomain::kBimanualDexterity, 5, 0.1},
             {GoalsDomain::kEfficiency, 3, 1.6},
             {GoalsDomain::kTissueHandling, 2, 2.5}};
  a.failed = 1;
  a.errors = 1;
  a.task_complete = false;
  a.pass = false;
  return a;
}

std::vector<ReportFrame> frames() { return {{0.8, "frames/error_0800.png", "grasper in the triangle of doom"}}; }

std::string report(const Assessment& a) {
  const std::vector<ReportFrame> f = frames();
  return assessment_html(synthetic_trace(), a, MetricSettings{}, f, "Session 7 — TAPP");
}

/// The text of the SVG element with `id`.
std::string svg_by_id(const std::string& html, const std::string& id) {
  const std::size_t start = html.find("<svg id=\"" + id + "\"");
  if (start == std::string::npos) return {};
  return html.substr(start, html.find("</svg>", start) - start);
}

TEST(ReportHtml, EscapesTheFiveSpecialCharacters) {
  EXPECT_EQ(html_escape("<a&b>\"'"), "&lt;a&amp;b&gt;&quot;&#39;");
  EXPECT_EQ(html_escape("plain text"), "plain text");
}

TEST(ReportHtml, FailComesFirstWithItsReasons) {
  const std::string html = report(failing_assessment());
  const std::size_t verdict = html.find("<div class=\"verdict fail\">FAIL</div>");
  ASSERT_NE(verdict, std::string::npos);
  EXPECT_LT(verdict, html.find("id=\"task\""));
  EXPECT_LT(verdict, html.find("id=\"metrics\""));
  EXPECT_EQ(html.find("verdict pass"), std::string::npos);
  EXPECT_NE(html.find("1 of 3 metrics below the expert level · 1 error · task incomplete (mesh fixed not done)"),
            std::string::npos);
}

TEST(ReportHtml, PassWhenTheAssessmentPasses) {
  Assessment a = failing_assessment();
  a.pass = true;
  a.failed = 0;
  a.errors = 0;
  a.task_complete = true;
  const std::string html = report(a);
  EXPECT_NE(html.find("<div class=\"verdict pass\">PASS</div>"), std::string::npos);
  EXPECT_EQ(html.find("verdict fail"), std::string::npos);
  EXPECT_NE(html.find("all 3 metrics at the expert level · no errors · task complete"), std::string::npos);
}

TEST(ReportHtml, TaskStepsAndCounts) {
  const std::string html = report(failing_assessment());
  EXPECT_NE(html.find("<td>mesh placed</td><td class=\"num\">1.20 s</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>mesh fixed</td><td class=\"notdone\">not done</td>"), std::string::npos);
  EXPECT_NE(html.find("Mesh coverage: <b>82.0 %</b>"), std::string::npos);
  EXPECT_NE(html.find("<b>1</b> into tissue only"), std::string::npos);
}

TEST(ReportHtml, MetricsScoredThenDetails) {
  const std::string html = report(failing_assessment());
  const std::size_t metrics = html.find("id=\"metrics\""), details = html.find("id=\"details\"");
  ASSERT_NE(metrics, std::string::npos);
  ASSERT_NE(details, std::string::npos);
  // The failing time row: value, mean ± SD, best quartile, pass mark, FAIL.
  const std::size_t time_row = html.find(
      "<td>Task time</td><td>s</td><td class=\"num\"><b>2.00</b></td>"
      "<td class=\"num\">1.50 ± 0.200</td><td class=\"num\">1.40</td>"
      "<td class=\"num\">≤ 1.90</td><td class=\"fail\">FAIL</td>");
  EXPECT_GT(time_row, metrics);
  EXPECT_LT(time_row, details);
  // Path length ≥ 0.1 m in m with two decimals; the 12 mm detail in mm, after the scored table.
  EXPECT_NE(html.find("<td>m</td><td class=\"num\"><b>0.35</b></td>"), std::string::npos);
  const std::size_t detail_row = html.find("<td>grasper_right path length</td><td>mm</td><td class=\"num\">12.0</td>");
  EXPECT_GT(detail_row, details);
  EXPECT_NE(detail_row, std::string::npos);
  EXPECT_EQ(std::count(html.begin(), html.end(), '\0'), 0);
  std::size_t pass_cells = 0;
  for (std::size_t at = html.find("<td class=\"pass\">PASS</td>"); at != std::string::npos;
       at = html.find("<td class=\"pass\">PASS</td>", at + 1))
    ++pass_cells;
  EXPECT_EQ(pass_cells, 2u);
}

TEST(ReportHtml, TraceTextIsEscapedAndThePageHasNoScriptNorNetwork) {
  const std::string html = report(failing_assessment());
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("peritoneum &lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_EQ(html.find("http:"), std::string::npos);
  EXPECT_EQ(html.find("https:"), std::string::npos);
  EXPECT_NE(html.find("<title>Session 7 — TAPP</title>"), std::string::npos);
}

TEST(ReportHtml, DamageThresholdSitsAtItsForceOnTheAxis) {
  const std::string plot = svg_by_id(report(failing_assessment()), "force-plot");
  ASSERT_FALSE(plot.empty());
  EXPECT_NE(plot.find("damage threshold 1.25 N"), std::string::npos);
  // The y tick labels (value, baseline y = tick y + 4) give the axis mapping.
  const std::regex tick_re(R"re(<text x="[^"]*" y="([^"]*)" text-anchor="end" class="ytick"[^>]*>([^<]*)</text>)re");
  std::vector<std::pair<double, double>> ticks;  // value, pixel y
  for (auto it = std::sregex_iterator(plot.begin(), plot.end(), tick_re); it != std::sregex_iterator(); ++it)
    ticks.emplace_back(std::stod((*it)[2]), std::stod((*it)[1]) - 4);
  ASSERT_GE(ticks.size(), 3u);
  const auto [v0, y0] = ticks.front();
  const auto [v1, y1] = ticks.back();
  EXPECT_GT(v1, 1.25);  // the axis reaches past the threshold (and the 1.6 N spike)
  const double expected_y = y0 + (1.25 - v0) * (y1 - y0) / (v1 - v0);
  std::smatch line;
  const std::regex line_re(R"re(<line x1="[^"]*" y1="([^"]*)" x2="[^"]*" y2="([^"]*)" class="threshold")re");
  ASSERT_TRUE(std::regex_search(plot, line, line_re));
  EXPECT_NEAR(std::stod(line[1]), expected_y, 0.15);
  EXPECT_EQ(line[1], line[2]);  // horizontal
}

/// The points attribute of every polyline in `text`, in order (found by hand: std::regex recurses
/// per character and a 20 kB attribute overflows the stack under AddressSanitizer).
std::vector<std::string> polyline_points(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t at = text.find("<polyline "); at != std::string::npos; at = text.find("<polyline ", at + 1)) {
    const std::size_t end = text.find('>', at);
    const std::size_t attr = text.find("points=\"", at);
    if (attr == std::string::npos || attr > end) continue;
    const std::size_t start = attr + 8;
    out.push_back(text.substr(start, text.find('"', start) - start));
  }
  return out;
}

TEST(ReportHtml, PolylinesAreThinnedAndTheSpikeSurvives) {
  const std::string html = report(failing_assessment());
  std::size_t lines = 0;
  for (const std::string& points : polyline_points(html)) {
    EXPECT_LE(std::count(points.begin(), points.end(), ' ') + 1, 1600);
    ++lines;
  }
  // 2 tissues + 2 instruments × 3 projections + 2 speeds.
  EXPECT_EQ(lines, 10u);
  // The 1 ms spike to ~1.9 N survives the min/max thinning: the peritoneum's line (the first)
  // rises above the damage threshold, which the rest of its sine (≤ 0.7 N) never reaches.
  const std::string plot = svg_by_id(html, "force-plot");
  const std::vector<std::string> plot_lines = polyline_points(plot);
  ASSERT_FALSE(plot_lines.empty());
  const std::string& points = plot_lines.front();
  double top_y = 1e9;
  for (std::size_t comma = points.find(','); comma != std::string::npos; comma = points.find(',', comma + 1))
    top_y = std::min(top_y, std::stod(points.substr(comma + 1)));
  const std::size_t threshold = plot.find("class=\"threshold\"");
  ASSERT_NE(threshold, std::string::npos);
  const std::size_t y1 = plot.rfind(" y1=\"", threshold);
  EXPECT_LT(top_y, std::stod(plot.substr(y1 + 5)));
}

TEST(ReportHtml, UnloadedTissueIsNotPlotted) {
  SessionTrace t = synthetic_trace();
  t.tissues.push_back({.name = "omentum", .force = std::vector<Real>(t.samples(), 0.0)});
  const std::string html = assessment_html(t, failing_assessment(), MetricSettings{}, {}, "x");
  EXPECT_EQ(svg_by_id(html, "force-plot").find("omentum"), std::string::npos);
}

/// The prosthetic mesh is not tissue: it has no line, no legend entry, and its load (5 N, far over
/// the damage threshold) does not stretch the force axis.
TEST(ReportHtml, ProstheticMeshIsNotPlottedAsTissue) {
  SessionTrace t = synthetic_trace();
  t.tissues.push_back({.name = "prosthetic mesh", .prosthetic = true, .force = std::vector<Real>(t.samples(), 5.0)});
  const std::string plot = svg_by_id(assessment_html(t, failing_assessment(), MetricSettings{}, {}, "x"), "force-plot");
  ASSERT_FALSE(plot.empty());
  EXPECT_EQ(plot.find("prosthetic mesh"), std::string::npos);
  EXPECT_EQ(polyline_points(plot).size(), 2u);
  const std::regex tick_re(R"re(class="ytick"[^>]*>([^<]*)</text>)re");
  double top_tick = 0;
  for (auto it = std::sregex_iterator(plot.begin(), plot.end(), tick_re); it != std::sregex_iterator(); ++it)
    top_tick = std::max(top_tick, std::stod((*it)[1]));
  EXPECT_GT(top_tick, 1.25);
  EXPECT_LT(top_tick, 5.0);
  // The same tissue, not marked prosthetic, is plotted (the check above is not vacuous).
  t.tissues.back().prosthetic = false;
  EXPECT_NE(svg_by_id(assessment_html(t, failing_assessment(), MetricSettings{}, {}, "x"), "force-plot")
                .find("prosthetic mesh"),
            std::string::npos);
}

TEST(ReportHtml, EmptySessionStillRenders) {
  const std::string html = assessment_html(SessionTrace{}, Assessment{}, MetricSettings{}, {}, "empty");
  EXPECT_NE(html.find("<div class=\"verdict fail\">FAIL</div>"), std::string::npos);
  EXPECT_NE(html.find("no expert reference · no errors"), std::string::npos);
  EXPECT_NE(html.find("no force on tissue recorded"), std::string::npos);
  EXPECT_EQ(html.find("nan"), std::string::npos);
  EXPECT_EQ(html.find("inf"), std::string::npos);
}

TEST(ReportHtml, SameInputSameBytes) { EXPECT_EQ(report(failing_assessment()), report(failing_assessment())); }

TEST(ReportHtml, FramesAndErrorsOnTheTimeline) {
  const std::string html = report(failing_assessment());
  EXPECT_NE(html.find("<img src=\"frames/error_0800.png\" width=\"320\""), std::string::npos);
  EXPECT_NE(html.find("0.80 s · grasper in the triangle of doom</figcaption>"), std::string::npos);
  const std::string timeline = svg_by_id(html, "timeline");
  EXPECT_NE(timeline.find(">zone force · triangle of doom</text>"), std::string::npos);
  EXPECT_NE(html.find("<tr class=\"error\"><td class=\"num\">0.80 s</td>"), std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"num\">1.50 s</td><td>tack</td>"), std::string::npos);
}

TEST(ReportHtml, ErrorsCloseInTimeGetTheirOwnLabelRows) {
  SessionTrace t = synthetic_trace();
  t.events = {{.time = 0.80, .kind = "zone force", .error = true, .place = Vec3::Zero(), .zone = "a", .text = ""},
              {.time = 0.81, .kind = "vessel grasped", .error = true, .place = Vec3::Zero(), .zone = "b", .text = ""},
              {.time = 1.90, .kind = "tack", .error = true, .place = Vec3::Zero(), .zone = "c", .text = ""}};
  const std::string timeline =
      svg_by_id(assessment_html(t, failing_assessment(), MetricSettings{}, {}, "x"), "timeline");
  auto label_y = [&](const std::string& label) {
    const std::size_t end = timeline.find(">" + label + "</text>");
    EXPECT_NE(end, std::string::npos) << label;
    const std::size_t y = timeline.rfind(" y=\"", end);
    return std::stod(timeline.substr(y + 4));
  };
  EXPECT_NE(label_y("zone force · a"), label_y("vessel grasped · b"));  // would overlap in one row
  EXPECT_EQ(label_y("zone force · a"), label_y("tack · c"));            // far apart: the same row
}

TEST(ReportHtml, GoalsRadarAndTable) {
  const std::string html = report(failing_assessment());
  const std::string radar = svg_by_id(html, "goals-radar");
  for (const char* label : {"depth perception", "bimanual dexterity", "efficiency", "tissue handling"})
    EXPECT_NE(radar.find(label), std::string::npos) << label;
  EXPECT_NE(radar.find("fill-rule=\"evenodd\""), std::string::npos);  // the 4–5 band
  EXPECT_NE(html.find("<td>tissue handling</td><td class=\"num\"><b>2</b></td>"), std::string::npos);
}

/// A whole page; with REPORT_EXAMPLE=path set it is also written there to look at (not a skip
/// otherwise: tests/allowed-skips.txt allows none here).
TEST(ReportHtml, IsOneWholePage) {
  const std::string html = report(failing_assessment());
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.substr(html.size() - 8), "</html>\n");
  EXPECT_LT(html.size(), 300000u);  // thinned plots keep the page small
  if (const char* path = std::getenv("REPORT_EXAMPLE")) {
    std::ofstream out(path);
    out << html;
    EXPECT_TRUE(out.good());
  }
}

}  // namespace
}  // namespace trocar
