// The learning-curve page on synthetic attempts (no recordings: each attempt's metrics are set by
// hand, so each check knows what the page must say): pass/fail per attempt against the pass mark
// in both directions, attempts to proficiency, the pass mark where the axis puts it, escaping,
// byte-for-byte determinism and the empty case.
#include "trocar/assessment/learning_curve_html.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>
#include <utility>
#include <vector>

namespace trocar {
namespace {

Metric metric(const std::string& id, const std::string& name, const std::string& unit, bool lower_is_better,
              Real value) {
  return Metric{.id = id,
                .name = name,
                .unit = unit,
                .domain = GoalsDomain::kEfficiency,
                .lower_is_better = lower_is_better,
                .scored = true,
                .value = value};
}

/// Five attempts: path length falls 2.0 → 0.8 m (passes from attempt 4), bimanual use rises but
/// dips at attempt 4 (proficient from 5), task time passes at 3 and 4 but not 5 (not yet), and a
/// metric the experts lack. Attempt 2's label carries markup.
std::vector<Attempt> attempts() {
  const Real path[] = {2.0, 1.6, 1.2, 0.9, 0.8};
  const Real bimanual[] = {40, 55, 72, 65, 85};
  const Real time[] = {900, 700, 500, 450, 620};
  const Real tacks[] = {14, 12, 11, 10, 9};
  std::vector<Attempt> out;
  for (int i = 0; i < 5; ++i) {
    Attempt a;
    a.label = i == 1 ? "<script>alert(1)</script> & co.trace" : "session_" + std::to_string(i + 1) + ".trace";
    a.metrics = {metric("path_length", "Path length, all instruments", "m", true, path[i]),
                 metric("bimanual", "Bimanual use", "%", false, bimanual[i]),
                 metric("time", "Task time", "s", true, time[i]), metric("tacks", "Tacks placed", "", true, tacks[i])};
    // A per-instrument detail: not scored, so no plot.
    Metric detail = metric("grasper_right.path_length", "grasper_right path length", "m", true, path[i] / 2);
    detail.scored = false;
    a.metrics.push_back(detail);
    a.pass = i >= 3;
    a.errors = i < 2 ? 2 - i : 0;
    out.push_back(a);
  }
  return out;
}

std::vector<ExpertStats> reference() {
  return {{.id = "path_length", .mean = 0.85, .sd = 0.1, .best_quartile = 0.8, .sessions = 12},
          {.id = "bimanual", .mean = 80, .sd = 5, .best_quartile = 84, .sessions = 12},
          {.id = "time", .mean = 420, .sd = 60, .best_quartile = 380, .sessions = 12}};
}

std::string page() {
  const std::vector<Attempt> a = attempts();
  return learning_curve_html(a, reference(), "Trainee 3 — TAPP");
}

/// The text of the SVG element with `id`.
std::string svg_by_id(const std::string& html, const std::string& id) {
  const std::size_t start = html.find("<svg id=\"" + id + "\"");
  if (start == std::string::npos) return {};
  return html.substr(start, html.find("</svg>", start) - start);
}

/// The points' classes in attempt order ("point pass", "point fail", "point").
std::vector<std::string> point_classes(const std::string& svg) {
  const std::regex re(R"re(<circle class="([^"]*)")re");
  std::vector<std::string> out;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

/// The "attempts to proficiency" cell of a metric's row in the proficiency table.
std::string proficiency_cell(const std::string& html, const std::string& id) {
  const std::size_t row = html.find("<tr data-metric=\"" + id + "\">");
  if (row == std::string::npos) return "(no row)";
  const std::string row_text = html.substr(row, html.find("</tr>", row) - row);
  const std::regex cell_re(R"re(<td class="to-proficiency[^"]*">([^<]*)</td>)re");
  std::smatch cell;
  return std::regex_search(row_text, cell, cell_re) ? std::string(cell[1]) : "(no cell)";
}

/// (value, pixel y) of the y tick labels of a plot: the label's baseline sits 4 px below its tick.
std::vector<std::pair<double, double>> y_ticks(const std::string& svg) {
  const std::regex re(R"re(<text x="[^"]*" y="([^"]*)" text-anchor="end" class="ytick"[^>]*>([^<]*)</text>)re");
  std::vector<std::pair<double, double>> out;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    out.emplace_back(std::stod((*it)[2]), std::stod((*it)[1]) - 4);
  return out;
}

TEST(LearningCurveHtml, FallingPathLengthPassesFromAttemptFour) {
  const std::string html = page();
  const std::string plot = svg_by_id(html, "curve-path_length");
  ASSERT_FALSE(plot.empty());
  EXPECT_EQ(point_classes(plot),
            (std::vector<std::string>{"point fail", "point fail", "point fail", "point pass", "point pass"}));
  EXPECT_EQ(proficiency_cell(html, "path_length"), "4");
  EXPECT_NE(html.find("<td class=\"num\">≤ 1.05</td><td class=\"num\">0.85</td><td class=\"num\">0.80</td>"),
            std::string::npos);
  // The points are joined in attempt order.
  EXPECT_NE(plot.find("<polyline "), std::string::npos);
}

TEST(LearningCurveHtml, HigherIsBetterPassesAboveThePassMark) {
  const std::string html = page();
  // Pass mark 80 − 2 × 5 = 70: 72 and 85 pass, 65 (attempt 4) falls back below it.
  EXPECT_EQ(point_classes(svg_by_id(html, "curve-bimanual")),
            (std::vector<std::string>{"point fail", "point fail", "point pass", "point fail", "point pass"}));
  EXPECT_EQ(proficiency_cell(html, "bimanual"), "5");
  EXPECT_NE(html.find("<td class=\"num\">≥ 70.0</td>"), std::string::npos);
}

TEST(LearningCurveHtml, NotYetWhileTheLatestAttemptFails) {
  const std::string html = page();
  EXPECT_EQ(point_classes(svg_by_id(html, "curve-time")),
            (std::vector<std::string>{"point fail", "point fail", "point pass", "point pass", "point fail"}));
  EXPECT_EQ(proficiency_cell(html, "time"), "not yet");
  EXPECT_NE(html.find("At the proficiency level in 2 of 3 metrics · 2 of 5 attempts passed overall"),
            std::string::npos);
}

TEST(LearningCurveHtml, MetricWithoutReferenceShowsItsValuesOnly) {
  const std::string html = page();
  const std::string plot = svg_by_id(html, "curve-tacks");
  ASSERT_FALSE(plot.empty());
  EXPECT_EQ(point_classes(plot), std::vector<std::string>(5, "point"));
  EXPECT_EQ(plot.find("pass-mark"), std::string::npos);
  EXPECT_EQ(plot.find("expert-mean"), std::string::npos);
  EXPECT_EQ(proficiency_cell(html, "tacks"), "no reference");
  // Details are not scored: no plot, no row.
  EXPECT_EQ(html.find("grasper_right path length"), std::string::npos);
}

TEST(LearningCurveHtml, AttemptsTableListsResultErrorsAndFailedMetrics) {
  const std::string html = page();
  EXPECT_NE(html.find("<tr><td class=\"num\">1</td><td>session_1.trace</td><td class=\"fail\">FAIL</td>"
                      "<td class=\"num\">2</td><td>3: Path length, all instruments, Bimanual use, Task time</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"num\">4</td><td>session_4.trace</td><td class=\"pass\">PASS</td>"
                      "<td class=\"num\">0</td><td>1: Bimanual use</td></tr>"),
            std::string::npos);
  EXPECT_LT(html.find("id=\"attempts\""), html.find("id=\"curves\""));
}

TEST(LearningCurveHtml, PassMarkAndPointsSitWhereTheAxisPutsThem) {
  const std::string plot = svg_by_id(page(), "curve-path_length");
  const auto ticks = y_ticks(plot);
  ASSERT_GE(ticks.size(), 3u);
  const auto [v0, y0] = ticks.front();
  const auto [v1, y1] = ticks.back();
  ASSERT_NE(v0, v1);
  const auto y_of = [&](double v) { return y0 + (v - v0) * (y1 - y0) / (v1 - v0); };
  EXPECT_LE(v0, 0.8);  // the axis holds every value and the lines
  EXPECT_GE(v1, 2.0);
  std::smatch line;
  const std::regex line_re(R"re(<line x1="[^"]*" y1="([^"]*)" x2="[^"]*" y2="([^"]*)" class="pass-mark")re");
  ASSERT_TRUE(std::regex_search(plot, line, line_re));
  EXPECT_NEAR(std::stod(line[1]), y_of(1.05), 0.15);
  EXPECT_EQ(line[1], line[2]);  // horizontal
  const std::regex mean_re(R"re(<line x1="[^"]*" y1="([^"]*)" x2="[^"]*" y2="[^"]*" class="expert-mean")re");
  ASSERT_TRUE(std::regex_search(plot, line, mean_re));
  EXPECT_NEAR(std::stod(line[1]), y_of(0.85), 0.15);
  // Attempt 4's point (0.9 m) below the pass mark on screen, attempt 1's (2.0 m) above it.
  const std::regex cy_re(R"re(<circle class="[^"]*" cx="[^"]*" cy="([^"]*)")re");
  std::vector<double> cys;
  for (auto it = std::sregex_iterator(plot.begin(), plot.end(), cy_re); it != std::sregex_iterator(); ++it)
    cys.push_back(std::stod((*it)[1]));
  ASSERT_EQ(cys.size(), 5u);
  EXPECT_NEAR(cys[3], y_of(0.9), 0.15);
  EXPECT_NEAR(cys[0], y_of(2.0), 0.15);
}

TEST(LearningCurveHtml, AttemptAxisHasWholeNumbers) {
  const std::string plot = svg_by_id(page(), "curve-path_length");
  const std::regex re(R"re(class="xtick"[^>]*>([^<]*)</text>)re");
  std::vector<std::string> labels;
  for (auto it = std::sregex_iterator(plot.begin(), plot.end(), re); it != std::sregex_iterator(); ++it)
    labels.push_back((*it)[1]);
  EXPECT_EQ(labels, (std::vector<std::string>{"1", "2", "3", "4", "5"}));
}

TEST(LearningCurveHtml, LabelsAreEscapedAndThePageHasNoScriptNorNetwork) {
  const std::string html = page();
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("<td>&lt;script&gt;alert(1)&lt;/script&gt; &amp; co.trace</td>"), std::string::npos);
  EXPECT_EQ(html.find("http:"), std::string::npos);
  EXPECT_EQ(html.find("https:"), std::string::npos);
  EXPECT_NE(html.find("<title>Trainee 3 — TAPP</title>"), std::string::npos);
}

TEST(LearningCurveHtml, SameInputSameBytes) { EXPECT_EQ(page(), page()); }

TEST(LearningCurveHtml, NoAttemptsSaysSo) {
  const std::string html = learning_curve_html({}, reference(), "Nobody yet");
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.substr(html.size() - 8), "</html>\n");
  EXPECT_NE(html.find("No attempts yet"), std::string::npos);
  EXPECT_EQ(html.find("<svg"), std::string::npos);
}

TEST(LearningCurveHtml, NoReferenceStillRenders) {
  const std::vector<Attempt> a = attempts();
  const std::string html = learning_curve_html(a, {}, "x");
  EXPECT_NE(html.find("No expert reference: values only, no pass marks."), std::string::npos);
  EXPECT_EQ(html.find("class=\"pass-mark\""), std::string::npos);
  EXPECT_EQ(html.find("nan"), std::string::npos);
  EXPECT_EQ(html.find("inf"), std::string::npos);
}

/// A whole page; with LEARNING_CURVE_EXAMPLE=path set it is also written there to look at.
TEST(LearningCurveHtml, IsOneWholePage) {
  const std::string html = page();
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.substr(html.size() - 8), "</html>\n");
  if (const char* path = std::getenv("LEARNING_CURVE_EXAMPLE")) {
    std::ofstream out(path);
    out << html;
    EXPECT_TRUE(out.good());
  }
}

}  // namespace
}  // namespace trocar
