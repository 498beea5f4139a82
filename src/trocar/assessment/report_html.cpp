#include "trocar/assessment/report_html.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "trocar/assessment/svg_plot.h"

namespace trocar {
namespace {

// The shared number, colour and SVG helpers (svg_plot.h); this file keeps the report's sections.
using namespace svg;

/// Seconds as "12.34 s", or "12 min 34.5 s" once minutes help.
std::string duration_text(Real seconds) {
  if (!(seconds >= 60)) return fixed(seconds, 2) + " s";
  const Real minutes = std::floor(seconds / 60);
  return fixed(minutes, 0) + " min " + fixed(seconds - 60 * minutes, 1) + " s";
}

std::string time_text(Real seconds) { return fixed(seconds, 2) + " s"; }

/// By the instrument's index in the trace, so it has one colour in every plot.
std::string instrument_colour(std::size_t i) { return palette_colour(i); }
/// Tissues take the palette from the other end, so they rarely share an instrument's colour.
std::string tissue_colour(std::size_t j) { return palette_colour(j, true); }

Real duration_of(const SessionTrace& trace) { return trace.time.empty() ? 0 : trace.time.back(); }

std::string instrument_label(const InstrumentTrace& inst, std::size_t i) {
  return inst.name.empty() ? "instrument " + std::to_string(i + 1) : inst.name;
}

// ---------------------------------------------------------------------------------------------
// Page sections

constexpr const char* kCss = R"(
main{max-width:960px;margin:0 auto;padding:24px}
header{display:flex;gap:24px;align-items:center;border-bottom:2px solid #ddd;padding-bottom:16px}
.verdict{font-size:56px;font-weight:800;letter-spacing:3px;color:#fff;border-radius:10px;padding:6px 30px;line-height:1.2}
.verdict.pass{background:#1b7f3a}.verdict.fail{background:#c62828}
h1{margin:0 0 2px;font-size:24px}
h2{font-size:19px;margin:30px 0 10px;padding-bottom:4px;border-bottom:1px solid #e3e3e3}
.why{font-size:17px;font-weight:600;margin-top:6px}
tr.error td{background:#fdecea}tr.error td:first-child{box-shadow:inset 4px 0 #c62828}
.notdone{color:#a31515;font-weight:600}table.narrow{width:auto;min-width:420px}
.goals{display:flex;gap:24px;align-items:flex-start;flex-wrap:wrap}.goals table{width:auto;min-width:320px}
svg{display:block;max-width:100%;height:auto;margin:6px 0}svg text{font-size:11px}
.frames{display:flex;flex-wrap:wrap;gap:16px;margin-top:8px}
figure{margin:0;width:320px}figure img{display:block;border:1px solid #ccc}figcaption{font-size:13px;margin-top:4px}
)";

std::size_t scored_count(const Assessment& a) {
  return static_cast<std::size_t>(std::count_if(
      a.metrics.begin(), a.metrics.end(), [](const MetricScore& m) { return m.metric.scored && m.has_reference; }));
}

/// The task's undone steps, "a, b".
std::string undone_steps(const TraceTask& task) {
  std::string out;
  for (const TraceStep& s : task.steps) {
    if (s.done_at >= 0) continue;
    out += (out.empty() ? "" : ", ") + s.name;
  }
  return out;
}

/// Why the session passed or failed, in one line: the three things the overall result rests on.
std::string verdict_reason(const SessionTrace& trace, const Assessment& a) {
  if (!a.assessable)
    return "not assessable: the simulation blew up at " + fixed(trace.unstable_at, 3) +
           " s (a simulator failure, not the trainee's); the numbers below are the blow-up's";
  const std::size_t scored = scored_count(a);
  std::string why;
  if (scored == 0) {
    why = "no expert reference";
  } else if (a.failed == 0) {
    why = "all " + std::to_string(scored) + " metrics at the expert level";
  } else {
    why = std::to_string(a.failed) + " of " + std::to_string(scored) + " metrics below the expert level";
  }
  why += " · " + (a.errors == 0 ? std::string("no errors") : plural(a.errors, "error", "errors"));
  if (trace.task.present) {
    const std::string undone = undone_steps(trace.task);
    if (a.task_complete) {
      why += " · task complete";
    } else {
      why += " · task incomplete" + (undone.empty() ? std::string() : " (" + undone + " not done)");
    }
  }
  return why;
}

void header_section(std::string& out, const SessionTrace& trace, const Assessment& a, const std::string& title) {
  const char* word = a.pass ? "PASS" : "FAIL";
  out += "<header>\n<div class=\"verdict " + std::string(a.pass ? "pass" : "fail") + "\">" + word + "</div>\n<div>\n";
  out += "<h1>" + html_escape(title) + "</h1>\n";
  out += "<div class=\"muted\">Scene <b>" + html_escape(trace.scene) + "</b> · duration " +
         duration_text(duration_of(trace)) + "</div>\n";
  out += "<div class=\"why\">" + html_escape(verdict_reason(trace, a)) + "</div>\n</div>\n</header>\n";
}

void task_section(std::string& out, const TraceTask& task) {
  out +=
      "<section id=\"task\">\n<h2>The task</h2>\n<table class=\"narrow\">\n<tr><th>Step</th><th class=\"num\">Done "
      "at</th></tr>\n";
  for (const TraceStep& s : task.steps) {
    out += "<tr><td>" + html_escape(s.name) + "</td>";
    out += s.done_at >= 0 ? "<td class=\"num\">" + time_text(s.done_at) + "</td>"
                          : std::string("<td class=\"notdone\">not done</td>");
    out += "</tr>\n";
  }
  out += "</table>\n<p>Tacks: <b>" + std::to_string(task.tacks) + "</b> placed · <b>" +
         std::to_string(task.fixed_tacks) + "</b> fixed · <b>" + std::to_string(task.zone_tacks) +
         "</b> in zones · <b>" + std::to_string(task.tissue_only_tacks) + "</b> into tissue only<br>\n";
  out += "Mesh coverage: <b>" + fixed(100 * task.coverage, 1) + " %</b>";
  if (task.sac_fraction > 0) out += " · sac reduced: <b>" + fixed(100 * task.sac_fraction, 1) + " %</b>";
  out += "</p>\n</section>\n";
}

constexpr GoalsDomain kDomains[] = {GoalsDomain::kDepthPerception, GoalsDomain::kBimanualDexterity,
                                    GoalsDomain::kEfficiency, GoalsDomain::kTissueHandling};

const GoalsScore* find_goal(const Assessment& a, GoalsDomain d) {
  for (const GoalsScore& g : a.goals)
    if (g.domain == d) return &g;
  return nullptr;
}

/// A ring of the radar at `score` (1…5) as SVG points: the four axes point up, right, down, left.
std::string radar_ring(Real cx, Real cy, Real radius_per_score, const Real (&scores)[4]) {
  constexpr int kDx[4] = {0, 1, 0, -1}, kDy[4] = {-1, 0, 1, 0};
  std::string points;
  for (int k = 0; k < 4; ++k) {
    if (k) points += ' ';
    points += px(cx + kDx[k] * radius_per_score * scores[k]) + "," + px(cy + kDy[k] * radius_per_score * scores[k]);
  }
  return points;
}

/// Four axes, the expert band (4–5, shaded) and the trainee's polygon.
std::string goals_radar(const Assessment& a) {
  constexpr Real cx = 270, cy = 175, per_score = 26;  // score 5 reaches 130 px
  std::string out;
  svg_open(out, "goals-radar", 540, 370, "GOALS radar chart");
  const Real four[4] = {4, 4, 4, 4}, five[4] = {5, 5, 5, 5};
  out += "<path d=\"M" + radar_ring(cx, cy, per_score, five) + "Z M" + radar_ring(cx, cy, per_score, four) +
         "Z\" fill=\"#2ca02c\" fill-opacity=\"0.22\" fill-rule=\"evenodd\" stroke=\"none\"/>\n";
  for (int s = 1; s <= 5; ++s) {
    const Real ring[4] = {Real(s), Real(s), Real(s), Real(s)};
    out += "<polygon points=\"" + radar_ring(cx, cy, per_score, ring) + "\" fill=\"none\" stroke=\"#d0d0d0\"/>\n";
    // A white halo keeps the ring's number readable where the trainee's outline crosses it.
    svg_text(out, cx + 4, cy - s * per_score + 12, std::to_string(s), "start",
             "fill=\"#777\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\"");
  }
  svg_line(out, cx, cy - 5 * per_score, cx, cy + 5 * per_score, "stroke=\"#999\"");
  svg_line(out, cx - 5 * per_score, cy, cx + 5 * per_score, cy, "stroke=\"#999\"");
  Real trainee[4];
  for (int k = 0; k < 4; ++k) {
    const GoalsScore* g = find_goal(a, kDomains[k]);
    trainee[k] = g ? std::clamp<Real>(g->score, 0, 5) : 0;
  }
  out += "<polygon id=\"trainee\" points=\"" + radar_ring(cx, cy, per_score, trainee) +
         "\" fill=\"#1f77b4\" fill-opacity=\"0.25\" stroke=\"#1f77b4\" stroke-width=\"2.5\"/>\n";
  const Real r = 5 * per_score + 10;
  svg_text(out, cx, cy - r, html_escape(to_string(kDomains[0])), "middle", "font-weight=\"600\" fill=\"#222\"");
  svg_text(out, cx + r, cy + 4, html_escape(to_string(kDomains[1])), "start", "font-weight=\"600\" fill=\"#222\"");
  svg_text(out, cx, cy + r + 10, html_escape(to_string(kDomains[2])), "middle", "font-weight=\"600\" fill=\"#222\"");
  svg_text(out, cx - r, cy + 4, html_escape(to_string(kDomains[3])), "end", "font-weight=\"600\" fill=\"#222\"");
  svg_legend(out, 150, 360, {{"trainee", "#1f77b4"}, {"expert band (4–5)", "#8fd18f"}}, false);
  out += "</svg>\n";
  return out;
}

void goals_section(std::string& out, const Assessment& a) {
  out += "<section id=\"goals\">\n<h2>GOALS summary</h2>\n<div class=\"goals\">\n<table>\n";
  out += "<tr><th>Domain</th><th class=\"num\">Score (1–5)</th><th class=\"num\">Mean z</th></tr>\n";
  for (const GoalsDomain d : kDomains) {
    const GoalsScore* g = find_goal(a, d);
    out += "<tr><td>" + html_escape(to_string(d)) + "</td>";
    if (g && g->score > 0) {
      out += "<td class=\"num\"><b>" + std::to_string(g->score) + "</b></td><td class=\"num\">" + fixed(g->mean_z, 2) +
             "</td>";
    } else {
      out += "<td class=\"num muted\">–</td><td class=\"muted\">no scored metric</td>";
    }
    out += "</tr>\n";
  }
  out += "</table>\n" + goals_radar(a) + "</div>\n</section>\n";
}

/// The unit a metric row is shown in, from the largest figure in the row.
DisplayUnit row_unit(const MetricScore& m) {
  Real magnitude = std::fabs(m.metric.value);
  if (m.has_reference) magnitude = std::max({magnitude, std::fabs(m.expert.mean), std::fabs(m.limit)});
  return display_unit(m.metric.unit, magnitude);
}

void scored_row(std::string& out, const MetricScore& m) {
  const DisplayUnit u = row_unit(m);
  out += "<tr><td>" + html_escape(m.metric.name.empty() ? m.metric.id : m.metric.name) + "</td><td>" +
         html_escape(u.unit) + "</td>";
  out += "<td class=\"num\"><b>" + show(m.metric.value, u) + "</b></td>";
  out += "<td class=\"num\">" + show(m.expert.mean, u) + " ± " + show_spread(m.expert.sd, u) + "</td>";
  out += "<td class=\"num\">" + show(m.expert.best_quartile, u) + "</td>";
  out += "<td class=\"num\">" + std::string(m.metric.lower_is_better ? "≤ " : "≥ ") + show(m.limit, u) + "</td>";
  out += m.pass ? "<td class=\"pass\">PASS</td>" : "<td class=\"fail\">FAIL</td>";
  out += "</tr>\n";
}

void detail_row(std::string& out, const MetricScore& m) {
  const DisplayUnit u = row_unit(m);
  out += "<tr><td>" + html_escape(m.metric.name.empty() ? m.metric.id : m.metric.name) + "</td><td>" +
         html_escape(u.unit) + "</td><td class=\"num\">" + show(m.metric.value, u) + "</td><td class=\"muted\">" +
         html_escape(to_string(m.metric.domain)) + "</td></tr>\n";
}

void metrics_section(std::string& out, const Assessment& a) {
  std::size_t sessions = 0;
  for (const MetricScore& m : a.metrics)
    if (m.has_reference) sessions = std::max(sessions, m.expert.sessions);
  out += "<section id=\"metrics\">\n<h2>Metrics against the experts</h2>\n";
  out += "<p class=\"muted\">Pass mark: the expert mean + 2 SD (− 2 SD where more is better)";
  if (sessions > 0) out += "; expert reference of " + plural(static_cast<int>(sessions), "session", "sessions");
  out +=
      ".</p>\n<table>\n<tr><th>Metric</th><th>Unit</th><th class=\"num\">Trainee</th><th class=\"num\">Expert mean ± "
      "SD</th>"
      "<th class=\"num\">Expert best quartile</th><th class=\"num\">Pass mark</th><th>Result</th></tr>\n";
  for (const MetricScore& m : a.metrics)
    if (m.metric.scored && m.has_reference) scored_row(out, m);
  out += "</table>\n</section>\n";
  out += "<section id=\"details\">\n<h2>Details</h2>\n<p class=\"muted\">Not compared with the experts.</p>\n";
  out += "<table>\n<tr><th>Metric</th><th>Unit</th><th class=\"num\">Value</th><th>GOALS domain</th></tr>\n";
  for (const MetricScore& m : a.metrics)
    if (!(m.metric.scored && m.has_reference)) detail_row(out, m);
  out += "</table>\n</section>\n";
}

/// Force on each loaded tissue over time, and the damage threshold. The prosthetic mesh is not
/// tissue: the threshold (a tissue's safe pull force) says nothing about it, so it is left out.
std::string force_plot(const SessionTrace& trace, const MetricSettings& settings) {
  const Real duration = duration_of(trace);
  Real top = settings.damage_force * 1.15;
  std::vector<std::size_t> loaded;
  for (std::size_t j = 0; j < trace.tissues.size(); ++j) {
    if (trace.tissues[j].prosthetic) continue;
    const Real m = max_of(trace.tissues[j].force);
    if (m > 0) loaded.push_back(j), top = std::max(top, m * 1.05);
  }
  const Panel p{70, 20, 600, 220, nice_scale(0, duration, 8), nice_scale(0, top, 6)};
  std::string out;
  svg_open(out, "force-plot", 900, 285, "Force on tissue over time");
  svg_axes(out, p, "time (s)", "force on tissue (N)");
  std::vector<LegendEntry> legend;
  for (const std::size_t j : loaded) {
    svg_series(out, p, trace.time, trace.tissues[j].force, tissue_colour(j));
    legend.push_back({trace.tissues[j].name, tissue_colour(j)});
  }
  if (loaded.empty())
    svg_text(out, p.left + p.width / 2, p.top + 40, "no force on tissue recorded", "middle", "fill=\"#666\"");
  const Real y = p.py_of(settings.damage_force);
  svg_line(out, p.left, y, p.left + p.width, y,
           "class=\"threshold\" stroke=\"" + std::string(kRed) + "\" stroke-width=\"1.6\" stroke-dasharray=\"7 4\"");
  svg_text(out, p.left + p.width - 4, y - 5, "damage threshold " + sig3(settings.damage_force) + " N", "end",
           "fill=\"" + std::string(kRed) + "\"");
  legend.push_back({"damage threshold", kRed, true});
  svg_legend(out, p.left + p.width + 20, p.top + 10, legend, true);
  out += "</svg>\n";
  return out;
}

/// Two ranges of the same length around the data, so that a square panel has equal scales on
/// both axes and a circle drawn by a tip looks like a circle.
std::pair<Scale, Scale> equal_scales(Real lo_a, Real hi_a, Real lo_b, Real hi_b) {
  const Real span = std::max({hi_a - lo_a, hi_b - lo_b, 1.0});
  const Real step = nice_step(span, 5);
  auto bounds = [step](Real lo, Real hi) {
    return std::pair<Real, Real>{std::floor(lo / step + 1e-9), std::ceil(hi / step - 1e-9)};
  };
  const auto [a0, a1] = bounds(lo_a, hi_a);
  const auto [b0, b1] = bounds(lo_b, hi_b);
  const Real n = std::max(a1 - a0, b1 - b0);
  auto centred = [&](Real first, Real last) {
    const Real lo = (first - std::floor((n - (last - first)) / 2)) * step;
    return Scale{lo, lo + n * step, step};
  };
  return {centred(a0, a1), centred(b0, b1)};
}

/// One projection of every instrument's tip path (cm), split where the instrument left the body.
void path_panel(std::string& out, const SessionTrace& trace, Real left, int a, int b) {
  constexpr Real kCm = 100;
  Real lo_a = 1e300, hi_a = -1e300, lo_b = 1e300, hi_b = -1e300;
  for (const InstrumentTrace& inst : trace.instruments)
    for (std::size_t i = 0; i < inst.tip.size() && i < inst.present.size(); ++i) {
      if (!inst.present[i]) continue;
      lo_a = std::min(lo_a, kCm * inst.tip[i][a]), hi_a = std::max(hi_a, kCm * inst.tip[i][a]);
      lo_b = std::min(lo_b, kCm * inst.tip[i][b]), hi_b = std::max(hi_b, kCm * inst.tip[i][b]);
    }
  if (lo_a > hi_a) lo_a = lo_b = 0, hi_a = hi_b = 1;
  const auto [sa, sb] = equal_scales(lo_a, hi_a, lo_b, hi_b);
  const Panel p{left, 20, 220, 220, sa, sb};
  const char* names = "xyz";
  svg_axes(out, p, std::string(1, names[a]) + " (cm)", std::string(1, names[b]) + " (cm)");
  for (std::size_t k = 0; k < trace.instruments.size(); ++k) {
    const InstrumentTrace& inst = trace.instruments[k];
    const std::size_t n = std::min(inst.tip.size(), inst.present.size());
    const std::size_t present = static_cast<std::size_t>(
        std::count(inst.present.begin(), inst.present.begin() + static_cast<std::ptrdiff_t>(n), 1));
    const std::size_t stride = std::max<std::size_t>(1, (present + kMaxPoints - 1) / kMaxPoints);
    std::vector<Point> segment;
    std::size_t seen = 0;
    for (std::size_t i = 0; i <= n; ++i) {
      const bool in = i < n && inst.present[i];
      const bool last_of_segment = in && (i + 1 == n || !inst.present[i + 1]);
      if (in && (seen++ % stride == 0 || last_of_segment))
        segment.push_back({p.px_of(kCm * inst.tip[i][a]), p.py_of(kCm * inst.tip[i][b])});
      if (!in && !segment.empty()) svg_polyline(out, segment, instrument_colour(k)), segment.clear();
    }
  }
}

/// Tip paths in the x–y, x–z and y–z planes, one colour per instrument.
std::string path_plot(const SessionTrace& trace) {
  std::string out;
  svg_open(out, "path-plot", 900, 310, "Instrument tip paths in three projections");
  path_panel(out, trace, 60, 0, 1);
  path_panel(out, trace, 360, 0, 2);
  path_panel(out, trace, 660, 1, 2);
  std::vector<LegendEntry> legend;
  for (std::size_t k = 0; k < trace.instruments.size(); ++k)
    legend.push_back({instrument_label(trace.instruments[k], k), instrument_colour(k)});
  svg_legend(out, 60, 300, legend, false);
  out += "</svg>\n";
  return out;
}

/// Tip speed (m/s) by backward differences; 0 where the instrument, or its previous sample, is
/// out of the body (a jump through the port is not motion).
std::vector<Real> tip_speed(const InstrumentTrace& inst, const std::vector<Real>& time, Real dt) {
  const std::size_t n = std::min(inst.tip.size(), inst.present.size());
  std::vector<Real> speed(n, 0);
  for (std::size_t i = 1; i < n; ++i) {
    if (!inst.present[i] || !inst.present[i - 1]) continue;
    const Real step = dt > 0 ? dt : (i < time.size() ? time[i] - time[i - 1] : 0);
    if (step > 0) speed[i] = (inst.tip[i] - inst.tip[i - 1]).norm() / step;
  }
  return speed;
}

/// Centred moving average (the window shrinks at the ends): finite differences of a 1 ms trace
/// are noisy, and the reader wants the speed the hand moved at.
std::vector<Real> moving_average(const std::vector<Real>& v, std::size_t window) {
  std::vector<Real> prefix(v.size() + 1, 0), out(v.size(), 0);
  for (std::size_t i = 0; i < v.size(); ++i) prefix[i + 1] = prefix[i] + v[i];
  const std::size_t half = window / 2;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::size_t lo = i >= half ? i - half : 0, hi = std::min(v.size(), i + half + 1);
    out[i] = (prefix[hi] - prefix[lo]) / static_cast<Real>(hi - lo);
  }
  return out;
}

/// Tip speed over time per instrument (mm/s, smoothed over 21 samples).
std::string speed_plot(const SessionTrace& trace) {
  std::vector<std::vector<Real>> speeds;
  Real top = 0;
  for (const InstrumentTrace& inst : trace.instruments) {
    std::vector<Real> s = moving_average(tip_speed(inst, trace.time, trace.dt), 21);
    for (Real& x : s) x *= 1000;
    top = std::max(top, max_of(s));
    speeds.push_back(std::move(s));
  }
  const Panel p{70, 20, 600, 220, nice_scale(0, duration_of(trace), 8), nice_scale(0, std::max(top * 1.05, 1.0), 6)};
  std::string out;
  svg_open(out, "speed-plot", 900, 285, "Tip speed over time");
  svg_axes(out, p, "time (s)", "tip speed (mm/s)");
  std::vector<LegendEntry> legend;
  for (std::size_t k = 0; k < speeds.size(); ++k) {
    svg_series(out, p, trace.time, speeds[k], instrument_colour(k));
    legend.push_back({instrument_label(trace.instruments[k], k), instrument_colour(k)});
  }
  svg_legend(out, p.left + p.width + 20, p.top + 10, legend, true);
  out += "</svg>\n";
  return out;
}

/// An error's label on the timeline: what happened and where.
std::string event_label(const TraceEvent& e) {
  return short_label(e.kind + (e.zone.empty() ? "" : " · " + e.zone), 34);
}

/// Rows for the error labels: each goes to the first row where it does not overlap the label
/// before it, so that errors close in time stay readable.
std::vector<int> label_rows(const std::vector<Real>& starts, const std::vector<Real>& widths, int max_rows) {
  std::vector<Real> row_end;
  std::vector<int> rows;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    int row = 0;
    while (row < static_cast<int>(row_end.size()) && row_end[row] + 8 > starts[i]) ++row;
    if (row >= max_rows) row = max_rows - 1;  // too many at once: overlap rather than a page of rows
    if (row >= static_cast<int>(row_end.size())) row_end.push_back(0);
    row_end[row] = starts[i] + widths[i];
    rows.push_back(row);
  }
  return rows;
}

/// The timeline's horizontal time axis.
struct TimeAxis {
  Real left = 90, width = 760;
  Scale s;
  Real x_of(Real t) const { return left + (t - s.lo) / (s.hi - s.lo) * width; }
};

/// An error's label placed on the timeline.
struct ErrorLabel {
  const TraceEvent* event = nullptr;
  std::string text;
  Real start = 0;  ///< px, left end of the text
  int row = 0;
};

std::vector<ErrorLabel> error_labels(const SessionTrace& trace, const TimeAxis& axis) {
  std::vector<ErrorLabel> labels;
  std::vector<Real> starts, widths;
  for (const TraceEvent& e : trace.events) {
    if (!e.error) continue;
    const std::string text = event_label(e);
    const Real w = text_width(text);
    const Real start = std::min(axis.x_of(e.time) - 4, axis.left + axis.width - w);  // inside the plot
    labels.push_back({&e, text, start, 0});
    starts.push_back(start);
    widths.push_back(w);
  }
  const std::vector<int> rows = label_rows(starts, widths, 8);
  for (std::size_t i = 0; i < labels.size(); ++i) labels[i].row = rows[i];
  return labels;
}

/// An event's dot; hovering it shows its time, kind and text.
void event_marker(std::string& out, const TraceEvent& e, Real x, Real y, Real radius, const char* colour) {
  out += "<circle cx=\"" + px(x) + "\" cy=\"" + px(y) + "\" r=\"" + px(radius) + "\" fill=\"" + colour + "\"><title>" +
         html_escape(time_text(e.time) + " " + e.kind + (e.text.empty() ? "" : ": " + e.text)) + "</title></circle>\n";
}

void timeline_axis(std::string& out, const TimeAxis& axis, Real y) {
  for (const Real t : ticks(axis.s)) {
    svg_line(out, axis.x_of(t), y, axis.x_of(t), y + 5, "stroke=\"#555\"");
    svg_text(out, axis.x_of(t), y + 17, fixed(t, tick_decimals(axis.s.step)), "middle", "fill=\"#333\"");
  }
  svg_line(out, axis.left, y, axis.left + axis.width, y, "stroke=\"#555\"");
  svg_text(out, axis.left + axis.width / 2, y + 34, "time (s)", "middle", "font-weight=\"600\" fill=\"#222\"");
  svg_text(out, axis.left - 10, y - 6, "events", "end", "fill=\"#555\"");
}

/// Numbered squares at the frames' times; the figures below the plot carry the same numbers.
void timeline_frames(std::string& out, const TimeAxis& axis, std::span<const ReportFrame> frames, Real y) {
  if (!frames.empty()) svg_text(out, axis.left - 10, y + 4, "frames", "end", "fill=\"#555\"");
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Real x = axis.x_of(frames[f].time);
    out += "<rect x=\"" + px(x - 7) + "\" y=\"" + px(y - 7) +
           "\" width=\"14\" height=\"14\" rx=\"2\" fill=\"#1f4e8c\"/>\n";
    svg_text(out, x, y + 4, std::to_string(f + 1), "middle", "fill=\"#fff\" font-weight=\"700\"");
  }
}

/// Errors (red, labelled), notes (grey) and the report's frames (numbered) on a time axis.
std::string timeline_plot(const SessionTrace& trace, std::span<const ReportFrame> frames) {
  const TimeAxis axis{90, 760, nice_scale(0, duration_of(trace), 10)};
  const std::vector<ErrorLabel> labels = error_labels(trace, axis);
  int rows = 0;
  for (const ErrorLabel& l : labels) rows = std::max(rows, l.row + 1);
  const Real axis_y = 44 + 16 * rows, frame_y = axis_y + 52, legend_y = frames.empty() ? axis_y + 56 : frame_y + 34;
  std::string out;
  svg_open(out, "timeline", 900, static_cast<int>(legend_y + 10), "Errors and events on a timeline");
  timeline_axis(out, axis, axis_y);
  for (const TraceEvent& e : trace.events)
    if (!e.error) event_marker(out, e, axis.x_of(e.time), axis_y - 10, 4, kGrey);
  const std::string red = "stroke=\"" + std::string(kRed) + "\" stroke-width=\"0.8\"";
  for (const ErrorLabel& l : labels) {
    const Real x = axis.x_of(l.event->time);
    svg_line(out, x, 27 + 16 * l.row, x, axis_y - 15, red);
    event_marker(out, *l.event, x, axis_y - 10, 5, kRed);
  }
  // Labels after every leader line, with a white halo, so a leader never crosses a label's text.
  for (const ErrorLabel& l : labels)
    svg_text(out, l.start, 24 + 16 * l.row, html_escape(l.text), "start",
             "fill=\"" + std::string(kRed) + "\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\"");
  timeline_frames(out, axis, frames, frame_y);
  std::vector<LegendEntry> legend{{"error", kRed}, {"note", kGrey}};
  if (!frames.empty()) legend.push_back({"frame (below)", "#1f4e8c"});
  svg_legend(out, axis.left, legend_y, legend, false);
  out += "</svg>\n";
  return out;
}

void frames_section(std::string& out, std::span<const ReportFrame> frames) {
  if (frames.empty()) return;
  out += "<div class=\"frames\">\n";
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const ReportFrame& fr = frames[f];
    out += "<figure><img src=\"" + html_escape(fr.image) + "\" width=\"320\" alt=\"" + html_escape(fr.caption) +
           "\"><figcaption><b>" + std::to_string(f + 1) + "</b> · " + time_text(fr.time) + " · " +
           html_escape(fr.caption) + "</figcaption></figure>\n";
  }
  out += "</div>\n";
}

void events_section(std::string& out, const SessionTrace& trace) {
  out += "<section id=\"events\">\n<h2>Events</h2>\n";
  if (trace.events.empty()) {
    out += "<p class=\"muted\">No events.</p>\n</section>\n";
    return;
  }
  out += "<table>\n<tr><th>Time</th><th>Kind</th><th>Zone</th><th>Description</th></tr>\n";
  for (const TraceEvent& e : trace.events) {
    out += e.error ? "<tr class=\"error\">" : "<tr>";
    out += "<td class=\"num\">" + time_text(e.time) + "</td><td>" + (e.error ? "<b>error</b>: " : std::string()) +
           html_escape(e.kind) + "</td><td>" + html_escape(e.zone) + "</td><td>" + html_escape(e.text) + "</td></tr>\n";
  }
  out += "</table>\n</section>\n";
}

void plots_section(std::string& out, const SessionTrace& trace, const MetricSettings& settings,
                   std::span<const ReportFrame> frames) {
  out += "<section id=\"plots\">\n<h2>Force on tissue</h2>\n" + force_plot(trace, settings);
  out += "<h2>Instrument tip paths</h2>\n" + path_plot(trace);
  out += "<h2>Tip speed</h2>\n<p class=\"muted\">Smoothed over 21 samples.</p>\n" + speed_plot(trace);
  out += "<h2>Errors over time</h2>\n" + timeline_plot(trace, frames);
  frames_section(out, frames);
  out += "</section>\n";
}

}  // namespace

std::string assessment_html(const SessionTrace& trace, const Assessment& assessment, const MetricSettings& settings,
                            std::span<const ReportFrame> frames, const std::string& title) {
  std::string out;
  page_start(out, title, kCss);
  header_section(out, trace, assessment, title);
  if (trace.task.present) task_section(out, trace.task);
  goals_section(out, assessment);
  metrics_section(out, assessment);
  plots_section(out, trace, settings, frames);
  events_section(out, trace);
  page_end(out);
  return out;
}

}  // namespace trocar
