#include "trocar/assessment/learning_curve_html.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "trocar/assessment/svg_plot.h"

namespace trocar {
namespace {

// The number, colour and SVG helpers the report uses too (svg_plot.h).
using namespace svg;

// ---------------------------------------------------------------------------------------------
// The curves: one scored metric over the attempts

/// One scored metric across the attempts.
struct Curve {
  Metric info;                              ///< id, name, unit and direction (from its first attempt)
  std::vector<std::optional<Real>> values;  ///< per attempt; empty where the attempt lacks the metric
  std::optional<ExpertStats> expert;        ///< none: no pass mark, values only
  Real pass_mark = 0;
};

/// As assess() decides it: a value on the pass mark passes.
bool passes(const Curve& c, Real value) { return meets(value, c.pass_mark, c.info.lower_is_better); }

std::optional<ExpertStats> find_expert(const std::vector<ExpertStats>& reference, const std::string& id) {
  for (const ExpertStats& e : reference)
    if (e.id == id) return e;
  return std::nullopt;
}

/// The scored metrics in the order they first appear (a later session may add one), each with
/// its value in every attempt that has it.
std::vector<Curve> curves_of(std::span<const Attempt> attempts, const std::vector<ExpertStats>& reference) {
  std::vector<Curve> curves;
  for (const Attempt& a : attempts)
    for (const Metric& m : a.metrics) {
      if (!m.scored) continue;
      if (std::any_of(curves.begin(), curves.end(), [&](const Curve& c) { return c.info.id == m.id; })) continue;
      Curve c{m, {}, find_expert(reference, m.id), 0};
      if (c.expert) c.pass_mark = trocar::pass_mark(*c.expert, m.lower_is_better);
      for (const Attempt& b : attempts) {
        const Metric* found = find_metric(b.metrics, m.id);
        // A non-finite value (a failed measurement) is shown as missing rather than off the plot.
        const bool usable = found && std::isfinite(found->value);
        c.values.push_back(usable ? std::optional<Real>(found->value) : std::nullopt);
      }
      curves.push_back(std::move(c));
    }
  return curves;
}

/// Attempts to proficiency: the first attempt (1-based) from which every later value passes; 0
/// while the latest value fails, or with no pass mark. An attempt without the metric neither
/// breaks nor starts a run.
int proficient_from(const Curve& c) {
  if (!c.expert) return 0;
  int from = 0;
  for (std::size_t i = 0; i < c.values.size(); ++i) {
    if (!c.values[i]) continue;
    if (!passes(c, *c.values[i])) {
      from = 0;
    } else if (from == 0) {
      from = static_cast<int>(i) + 1;
    }
  }
  return from;
}

std::string metric_name(const Metric& m) { return m.name.empty() ? m.id : m.name; }

/// The names of the metrics attempt `i` fails.
std::vector<std::string> failed_in(const std::vector<Curve>& curves, std::size_t i) {
  std::vector<std::string> names;
  for (const Curve& c : curves)
    if (c.expert && c.values[i] && !passes(c, *c.values[i])) names.push_back(metric_name(c.info));
  return names;
}

/// The unit a curve is shown in, from the largest figure it has (as the report's rows).
DisplayUnit unit_of(const Curve& c) {
  Real magnitude = 0;
  for (const std::optional<Real>& v : c.values)
    if (v) magnitude = std::max(magnitude, std::fabs(*v));
  if (c.expert) magnitude = std::max({magnitude, std::fabs(c.expert->mean), std::fabs(c.pass_mark)});
  return display_unit(c.info.unit, magnitude);
}

/// Attempts to proficiency as a reader sees it: "4", "not yet", or "no reference".
std::string proficiency_text(const Curve& c) {
  if (!c.expert) return "no reference";
  const int from = proficient_from(c);
  return from > 0 ? std::to_string(from) : "not yet";
}

// ---------------------------------------------------------------------------------------------
// One small plot per curve

constexpr int kPlotWidth = 380, kPlotHeight = 220;
constexpr const char* kValueColour = "#1f4e8c";

/// Every attempt up to a dozen, then a nice whole step (1, 2, 5, 10, …) so the labels stay apart.
std::vector<Real> attempt_ticks(std::size_t n) {
  const Real step = n <= 12 ? 1 : std::max<Real>(1, nice_step(static_cast<Real>(n), 8));
  std::vector<Real> out{1};
  for (Real k = step; k <= static_cast<Real>(n); k += step)
    if (k > 1) out.push_back(k);
  return out;
}

/// The value range (display unit) holding the values, the pass mark and the mean with a margin,
/// so that no point sits on the frame; not below 0 for a metric that never is.
Scale value_scale(const Curve& c, const DisplayUnit& u) {
  std::vector<Real> all;
  for (const std::optional<Real>& v : c.values)
    if (v && std::isfinite(*v)) all.push_back(*v * u.factor);
  if (c.expert) all.insert(all.end(), {c.pass_mark * u.factor, c.expert->mean * u.factor});
  if (all.empty()) return nice_scale(0, 1, 5);
  const auto [lo, hi] = std::minmax_element(all.begin(), all.end());
  const Real margin = 0.06 * (*hi - *lo);
  const Real bottom = *lo >= 0 ? std::max<Real>(0, *lo - margin) : *lo - margin;
  return nice_scale(bottom, *hi + margin, 5);
}

Panel curve_panel(const Curve& c, const DisplayUnit& u) {
  const Real n = static_cast<Real>(c.values.size());
  // Half an attempt of room either side, so the first and last points are off the frame.
  return Panel{58, 12, 306, 158, Scale{0.5, n + 0.5, 1}, value_scale(c, u)};
}

/// The pixel position of each attempt's value (attempts without the metric left out).
std::vector<Point> value_positions(const Panel& p, const Curve& c, const DisplayUnit& u) {
  std::vector<Point> out;
  for (std::size_t i = 0; i < c.values.size(); ++i)
    if (c.values[i]) out.push_back({p.px_of(static_cast<Real>(i + 1)), p.py_of(*c.values[i] * u.factor)});
  return out;
}

/// A horizontal reference line across the panel (its label comes after the values, on top).
void reference_line(std::string& out, const Panel& p, Real value, const char* css_class, const char* colour,
                    const char* dash) {
  const Real y = p.py_of(value);
  svg_line(out, p.left, y, p.left + p.width, y,
           "class=\"" + std::string(css_class) + "\" stroke=\"" + colour +
               "\" stroke-width=\"1.6\" stroke-dasharray=\"" + dash + "\"");
}

void reference_lines(std::string& out, const Panel& p, const Curve& c, const DisplayUnit& u) {
  if (!c.expert) return;
  reference_line(out, p, c.expert->mean * u.factor, "expert-mean", kGrey, "2 3");
  reference_line(out, p, c.pass_mark * u.factor, "pass-mark", kRed, "7 4");
}

/// A reference line's label: at one end of the line, above or below it.
struct LineLabel {
  std::string text;
  Real line_y = 0;
  bool left_end = false;
  bool above = false;
  Real x(const Panel& p) const { return left_end ? p.left + 4 : p.left + p.width - 4; }
  Real baseline() const { return above ? line_y - 5 : line_y + 13; }
};

/// Whether the label's text would cover a point (its dot) or the line between two points.
bool covers_the_curve(const LineLabel& label, const Panel& p, const std::vector<Point>& points) {
  const Real width = text_width(label.text);
  const Real x0 = label.left_end ? label.x(p) : label.x(p) - width, x1 = x0 + width;
  const Real y0 = label.baseline() - 11, y1 = label.baseline() + 3;
  const auto near = [&](Point q, Real margin) {
    return q.x > x0 - margin && q.x < x1 + margin && q.y > y0 - margin && q.y < y1 + margin;
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (near(points[i], 5)) return true;
    if (i == 0) continue;
    const Point a = points[i - 1], b = points[i];
    for (int k = 1; k < 16; ++k) {  // the segment from the previous point, sampled every few px
      const Real f = k / 16.0;
      if (near({a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)}, 1)) return true;
    }
  }
  return false;
}

/// The label at its preferred end, or at the other where only that one leaves the curve clear.
void place_label(std::string& out, const Panel& p, LineLabel label, const char* colour,
                 const std::vector<Point>& points) {
  if (covers_the_curve(label, p, points)) {
    LineLabel other = label;
    other.left_end = !label.left_end;
    if (!covers_the_curve(other, p, points)) label = other;
  }
  // A white halo keeps it readable where the curve still crosses it.
  svg_text(out, label.x(p), label.baseline(), html_escape(label.text), label.left_end ? "start" : "end",
           "fill=\"" + std::string(colour) + "\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\"");
}

/// A trainee usually fails early and passes late: the pass mark is labelled at the right end on
/// the failing side, the mean at the left end on the passing side, where few points fall; the two
/// labels part even where the lines are close.
void reference_labels(std::string& out, const Panel& p, const Curve& c, const DisplayUnit& u) {
  if (!c.expert) return;
  const bool lower = c.info.lower_is_better;
  const std::vector<Point> points = value_positions(p, c, u);
  place_label(out, p, {"expert mean", p.py_of(c.expert->mean * u.factor), true, !lower}, kGrey, points);
  place_label(out, p, {"pass mark", p.py_of(c.pass_mark * u.factor), false, lower}, kRed, points);
}

/// A light band from the attempt of proficiency on: where the trainee stays at the expert level.
void proficient_band(std::string& out, const Panel& p, const Curve& c) {
  const int from = proficient_from(c);
  if (from == 0) return;
  const Real x = p.px_of(from - 0.5);
  out += "<rect class=\"proficient\" x=\"" + px(x) + "\" y=\"" + px(p.top) + "\" width=\"" +
         px(p.left + p.width - x) + "\" height=\"" + px(p.height) + "\" fill=\"" + kGreen +
         "\" fill-opacity=\"0.08\"/>\n";
}

/// One attempt's dot, green where it passes and red where it fails (neutral with no pass mark);
/// hovering it shows the attempt, its label and value.
void value_dot(std::string& out, const Panel& p, const Curve& c, const DisplayUnit& u, std::size_t i,
               const std::string& attempt_label) {
  const Real v = *c.values[i];
  const char* result = !c.expert ? "" : passes(c, v) ? " pass" : " fail";
  const char* fill = !c.expert ? kValueColour : passes(c, v) ? kGreen : kRed;
  const std::string tip = "attempt " + std::to_string(i + 1) + " · " + attempt_label + ": " + show(v, u) +
                          (u.unit.empty() ? "" : " " + u.unit) + (*result ? std::string(" ·") + result : "");
  out += "<circle class=\"point" + std::string(result) + "\" cx=\"" + px(p.px_of(static_cast<Real>(i + 1))) +
         "\" cy=\"" + px(p.py_of(v * u.factor)) + "\" r=\"4.5\" fill=\"" + fill +
         "\" stroke=\"#fff\" stroke-width=\"1.5\"><title>" + html_escape(tip) + "</title></circle>\n";
}

/// The values joined in attempt order, then a dot per attempt.
void value_points(std::string& out, const Panel& p, const Curve& c, const DisplayUnit& u,
                  std::span<const Attempt> attempts) {
  svg_polyline(out, value_positions(p, c, u), kValueColour);
  for (std::size_t i = 0; i < c.values.size(); ++i)
    if (c.values[i]) value_dot(out, p, c, u, i, attempts[i].label);
}

std::string curve_plot(const Curve& c, std::span<const Attempt> attempts) {
  const DisplayUnit u = unit_of(c);
  const Panel p = curve_panel(c, u);
  std::string out;
  svg_open(out, "curve-" + html_escape(c.info.id), kPlotWidth, kPlotHeight, metric_name(c.info) + " by attempt");
  proficient_band(out, p, c);
  svg_x_ticks(out, p, attempt_ticks(c.values.size()), 0);
  svg_y_ticks(out, p);
  svg_frame(out, p, "attempt", u.unit.empty() ? "value" : u.unit);
  reference_lines(out, p, c, u);
  value_points(out, p, c, u, attempts);
  reference_labels(out, p, c, u);
  out += "</svg>\n";
  return out;
}

// ---------------------------------------------------------------------------------------------
// Page sections

constexpr const char* kCss = R"(
main{max-width:1220px;margin:0 auto;padding:24px}
header{border-bottom:2px solid #ddd;padding-bottom:12px}
h1{margin:0 0 4px;font-size:24px}
h2{font-size:19px;margin:28px 0 10px;padding-bottom:4px;border-bottom:1px solid #e3e3e3}
.summary{font-size:17px;font-weight:600}
td.notyet{color:#a31515;font-weight:600}td.reached{color:#14602c;font-weight:600}
.curves{display:flex;flex-wrap:wrap;gap:14px 18px;margin-top:8px}
figure.curve{margin:0;width:380px;border:1px solid #e3e3e3;border-radius:6px;padding:8px 0 2px}
figure.curve figcaption{padding:0 12px;font-size:14px;line-height:1.3}
svg{display:block;max-width:100%;height:auto}svg text{font-size:11px}
)";

/// The attempt from which every metric with a pass mark stays passing (0: not yet or none).
int all_proficient_from(const std::vector<Curve>& curves) {
  int from = 0;
  for (const Curve& c : curves) {
    if (!c.expert) continue;
    const int f = proficient_from(c);
    if (f == 0) return 0;
    from = std::max(from, f);
  }
  return from;
}

/// The one line a supervisor reads first: where the trainee stands now.
std::string summary_line(std::span<const Attempt> attempts, const std::vector<Curve>& curves) {
  const int with_reference = static_cast<int>(
      std::count_if(curves.begin(), curves.end(), [](const Curve& c) { return c.expert.has_value(); }));
  if (with_reference == 0) return "No expert reference: values only, no pass marks.";
  const int reached = static_cast<int>(
      std::count_if(curves.begin(), curves.end(), [](const Curve& c) { return proficient_from(c) > 0; }));
  const int from = all_proficient_from(curves);
  std::string line = from > 0 ? "At the proficiency level in every metric from attempt " + std::to_string(from)
                              : "At the proficiency level in " + std::to_string(reached) + " of " +
                                    plural(with_reference, "metric", "metrics");
  const int passed = static_cast<int>(
      std::count_if(attempts.begin(), attempts.end(), [](const Attempt& a) { return a.pass; }));
  return line + " · " + std::to_string(passed) + " of " +
         plural(static_cast<int>(attempts.size()), "attempt", "attempts") + " passed overall";
}

void header_section(std::string& out, std::span<const Attempt> attempts, const std::vector<Curve>& curves,
                    const std::vector<ExpertStats>& reference, const std::string& title) {
  std::size_t sessions = 0;
  for (const ExpertStats& e : reference) sessions = std::max(sessions, e.sessions);
  out += "<header>\n<h1>" + html_escape(title) + "</h1>\n<div class=\"muted\">Learning curve · " +
         plural(static_cast<int>(attempts.size()), "attempt", "attempts") + " · " +
         plural(static_cast<int>(curves.size()), "scored metric", "scored metrics");
  if (sessions > 0) out += " · expert reference of " + plural(static_cast<int>(sessions), "session", "sessions");
  out += "</div>\n<div class=\"summary\">" + html_escape(summary_line(attempts, curves)) + "</div>\n</header>\n";
}

std::string failed_text(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string out = std::to_string(names.size()) + ":";
  for (std::size_t k = 0; k < names.size(); ++k) out += (k ? ", " : " ") + names[k];
  return out;
}

void attempts_section(std::string& out, std::span<const Attempt> attempts, const std::vector<Curve>& curves) {
  out += "<section id=\"attempts\">\n<h2>Attempts</h2>\n<table>\n";
  out +=
      "<tr><th class=\"num\">#</th><th>Session</th><th>Result</th><th class=\"num\">Errors</th>"
      "<th>Metrics failed</th></tr>\n";
  for (std::size_t i = 0; i < attempts.size(); ++i) {
    const Attempt& a = attempts[i];
    out += "<tr><td class=\"num\">" + std::to_string(i + 1) + "</td><td>" + html_escape(a.label) + "</td>";
    out += a.pass ? "<td class=\"pass\">PASS</td>" : "<td class=\"fail\">FAIL</td>";
    out += "<td class=\"num\">" + std::to_string(a.errors) + "</td><td>" +
           html_escape(failed_text(failed_in(curves, i))) + "</td></tr>\n";
  }
  out += "</table>\n</section>\n";
}

/// The latest value a curve has (the trainee's current level).
std::optional<Real> latest(const Curve& c) {
  for (std::size_t i = c.values.size(); i-- > 0;)
    if (c.values[i]) return c.values[i];
  return std::nullopt;
}

void proficiency_row(std::string& out, const Curve& c) {
  const DisplayUnit u = unit_of(c);
  const std::optional<Real> last = latest(c);
  out += "<tr data-metric=\"" + html_escape(c.info.id) + "\"><td>" + html_escape(metric_name(c.info)) + "</td><td>" +
         html_escape(u.unit) + "</td>";
  if (c.expert) {
    out += "<td class=\"num\">" + std::string(c.info.lower_is_better ? "≤ " : "≥ ") + show(c.pass_mark, u) +
           "</td><td class=\"num\">" + show(c.expert->mean, u) + "</td>";
  } else {
    out += "<td class=\"num muted\">–</td><td class=\"num muted\">–</td>";
  }
  out += "<td class=\"num\">" + (last ? show(*last, u) : std::string("–")) + "</td>";
  const char* state = !c.expert ? "muted" : proficient_from(c) > 0 ? "reached" : "notyet";
  out += "<td class=\"to-proficiency " + std::string(state) + "\">" + proficiency_text(c) + "</td></tr>\n";
}

void proficiency_section(std::string& out, const std::vector<Curve>& curves) {
  out += "<section id=\"proficiency\">\n<h2>Attempts to proficiency</h2>\n";
  out +=
      "<p class=\"muted\">Pass mark: the expert mean + 2 SD (− 2 SD where more is better). Attempts to proficiency: "
      "the first attempt from which the metric stays at the pass mark or better.</p>\n<table>\n";
  out +=
      "<tr><th>Metric</th><th>Unit</th><th class=\"num\">Pass mark</th><th class=\"num\">Expert mean</th>"
      "<th class=\"num\">Latest</th><th>Attempts to proficiency</th></tr>\n";
  for (const Curve& c : curves) proficiency_row(out, c);
  out += "</table>\n</section>\n";
}

/// What the lines, dots and band of every plot mean, once for the page.
std::string plots_legend() {
  std::string out;
  svg_open(out, "curve-legend", 900, 26, "Legend of the learning-curve plots");
  svg_line(out, 4, 13, 30, 13, "stroke=\"" + std::string(kRed) + "\" stroke-width=\"2\" stroke-dasharray=\"7 4\"");
  svg_text(out, 36, 17, "pass mark (expert mean ± 2 SD)");
  svg_line(out, 246, 13, 272, 13, "stroke=\"" + std::string(kGrey) + "\" stroke-width=\"2\" stroke-dasharray=\"2 3\"");
  svg_text(out, 278, 17, "expert mean");
  out += "<circle cx=\"372\" cy=\"13\" r=\"4.5\" fill=\"" + std::string(kGreen) + "\"/>\n";
  svg_text(out, 382, 17, "attempt passes");
  out += "<circle cx=\"492\" cy=\"13\" r=\"4.5\" fill=\"" + std::string(kRed) + "\"/>\n";
  svg_text(out, 502, 17, "attempt fails");
  out += "<rect x=\"600\" y=\"5\" width=\"26\" height=\"16\" fill=\"" + std::string(kGreen) +
         "\" fill-opacity=\"0.15\" stroke=\"#ccc\"/>\n";
  svg_text(out, 632, 17, "proficient from here on");
  out += "</svg>\n";
  return out;
}

/// The metric's name (and unit), then its direction and attempts to proficiency, in two lines
/// that fit the plot's width so that the plots of a row line up.
std::string curve_caption(const Curve& c) {
  const DisplayUnit u = unit_of(c);
  const int from = proficient_from(c);
  std::string status = !c.expert   ? "no expert reference"
                       : from > 0 ? "proficient from attempt " + std::to_string(from)
                                  : "not yet proficient";
  // A long name is cut to keep the caption to two lines (so the plots of a row line up); the whole
  // name stays as a tooltip.
  const std::string name = metric_name(c.info), shown = short_label(name, 36);
  const std::string tip = shown == name ? "" : " title=\"" + html_escape(name) + "\"";
  return "<figcaption><b" + tip + ">" + html_escape(shown) + "</b>" +
         (u.unit.empty() ? "" : " (" + html_escape(u.unit) + ")") + "<br><span class=\"muted\">" +
         (c.info.lower_is_better ? "lower is better" : "higher is better") + " · " + status +
         "</span></figcaption>\n";
}

void curves_section(std::string& out, std::span<const Attempt> attempts, const std::vector<Curve>& curves) {
  out += "<section id=\"curves\">\n<h2>Metrics by attempt</h2>\n" + plots_legend() + "<div class=\"curves\">\n";
  for (const Curve& c : curves)
    out += "<figure class=\"curve\">\n" + curve_caption(c) + curve_plot(c, attempts) + "</figure>\n";
  out += "</div>\n</section>\n";
}

}  // namespace

std::string learning_curve_html(std::span<const Attempt> attempts, const std::vector<ExpertStats>& reference,
                                const std::string& title) {
  std::string out;
  page_start(out, title, kCss);
  if (attempts.empty()) {
    out += "<header>\n<h1>" + html_escape(title) + "</h1>\n</header>\n";
    out += "<p id=\"no-attempts\" class=\"summary\">No attempts yet: the learning curve starts with the first "
           "recorded session.</p>\n";
    page_end(out);
    return out;
  }
  const std::vector<Curve> curves = curves_of(attempts, reference);
  header_section(out, attempts, curves, reference, title);
  attempts_section(out, attempts, curves);
  proficiency_section(out, curves);
  curves_section(out, attempts, curves);
  page_end(out);
  return out;
}

}  // namespace trocar
