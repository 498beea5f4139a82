#include "trocar/assessment/svg_plot.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace trocar {

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// The style both pages share (the report and the learning curve).
constexpr const char* kBaseCss = R"(
body{font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,Helvetica,Arial,sans-serif;color:#1d1d1f;margin:0;background:#fff}
.muted{color:#666}
table{border-collapse:collapse;width:100%;font-size:14px;margin:6px 0}
th,td{padding:4px 8px;border-bottom:1px solid #e6e6e6;text-align:left;vertical-align:top}
th{background:#f3f4f6;font-weight:600}th.num{text-align:right}
td.num{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums}
td.pass,td.fail{text-align:center;font-weight:700}
td.pass{background:#dcf2e2;color:#14602c}td.fail{background:#fbdada;color:#a31515}
)";

void page_start(std::string& out, const std::string& title, const char* css) {
  out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + html_escape(title) + "</title>\n<style>" + std::string(kBaseCss) + css +
         "</style>\n</head>\n<body>\n<main>\n";
}

void page_end(std::string& out) { out += "</main>\n</body>\n</html>\n"; }

namespace svg {

// ---------------------------------------------------------------------------------------------
// Numbers as text

/// std::to_chars ignores the C locale, so a page is the same bytes on every machine (a ","
/// decimal separator would also break the SVG coordinates).
std::string fixed(Real v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char buf[512];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  if (r.ec != std::errc{}) return "–";
  std::string s(buf, r.ptr);
  // A tiny negative rounds to "-0.00": say "0.00".
  if (s.front() == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

/// A surgeon reads "0.00123", not "1.23e-03".
std::string sig3(Real v) {
  if (!std::isfinite(v)) return "–";
  if (v == 0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::fabs(v))));
  int decimals = std::clamp(2 - magnitude, 0, 9);
  // 9.996 rounds to 10.0: one decimal fewer keeps three digits.
  if (decimals > 0 && std::fabs(std::round(v * std::pow(10.0, decimals))) >= std::pow(10.0, 3)) --decimals;
  return fixed(v, decimals);
}

/// A tenth of a pixel is finer than any screen and keeps the file small.
std::string px(Real v) { return fixed(v, 1); }

std::string plural(int n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); }

DisplayUnit display_unit(const std::string& unit, Real magnitude) {
  if (unit == "m") return magnitude >= 0.1 ? DisplayUnit{"m", 1, 2} : DisplayUnit{"mm", 1000, -1};
  return DisplayUnit{unit, 1, -1};
}

std::string show(Real v, const DisplayUnit& u) {
  return u.decimals < 0 ? sig3(v * u.factor) : fixed(v * u.factor, u.decimals);
}

std::string show_spread(Real v, const DisplayUnit& u) {
  if (u.decimals >= 0 && std::fabs(v * u.factor) >= std::pow(10.0, -u.decimals)) return show(v, u);
  return sig3(v * u.factor);
}

std::string palette_colour(std::size_t i, bool from_end) {
  return kPalette[from_end ? kPaletteSize - 1 - i % kPaletteSize : i % kPaletteSize];
}

// ---------------------------------------------------------------------------------------------
// Scales

Real nice_step(Real span, int ticks) {
  const Real raw = span / std::max(ticks, 1);
  const Real magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const Real f = raw / magnitude;
  return (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * magnitude;
}

Scale nice_scale(Real lo, Real hi, int ticks) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  // An empty range (a constant series) is widened by 10 % (by 1 around 0) so that it has ticks.
  if (hi - lo <= 1e-12 * std::max(1.0, std::fabs(hi))) {
    const Real pad = lo == 0 ? 1 : 0.1 * std::fabs(lo);
    lo -= lo == 0 ? 0 : pad;
    hi += pad;
  }
  const Real step = nice_step(hi - lo, ticks);
  return {std::floor(lo / step + 1e-9) * step, std::ceil(hi / step - 1e-9) * step, step};
}

std::vector<Real> ticks(const Scale& s) {
  std::vector<Real> out;
  const int n = static_cast<int>(std::lround((s.hi - s.lo) / s.step));
  for (int i = 0; i <= n; ++i) {
    const Real v = s.lo + i * s.step;
    out.push_back(std::fabs(v) < 1e-6 * s.step ? 0 : v);  // no "-0" label
  }
  return out;
}

int tick_decimals(Real step) { return std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9))); }

// ---------------------------------------------------------------------------------------------
// SVG elements

void svg_open(std::string& out, const std::string& id, int width, int height, const std::string& label) {
  out += "<svg id=\"" + id + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
         "\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
         "\" role=\"img\" aria-label=\"" + html_escape(label) + "\">\n";
}

void svg_text(std::string& out, Real x, Real y, const std::string& escaped, const char* anchor,
              const std::string& extra) {
  out += "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\" text-anchor=\"" + anchor + "\"" +
         (extra.empty() ? "" : " " + extra) + ">" + escaped + "</text>\n";
}

void svg_line(std::string& out, Real x1, Real y1, Real x2, Real y2, const std::string& style) {
  out +=
      "<line x1=\"" + px(x1) + "\" y1=\"" + px(y1) + "\" x2=\"" + px(x2) + "\" y2=\"" + px(y2) + "\" " + style + "/>\n";
}

namespace {
constexpr const char* kGridStyle = "stroke=\"#e4e4e4\" stroke-width=\"1\"";
}  // namespace

void svg_x_ticks(std::string& out, const Panel& p, const std::vector<Real>& values, int decimals) {
  for (const Real v : values) {
    const Real x = p.px_of(v);
    svg_line(out, x, p.top, x, p.top + p.height, kGridStyle);
    svg_text(out, x, p.top + p.height + 15, fixed(v, decimals), "middle", "class=\"xtick\" fill=\"#333\"");
  }
}

void svg_y_ticks(std::string& out, const Panel& p) {
  const int decimals = tick_decimals(p.y.step);
  for (const Real v : ticks(p.y)) {
    const Real y = p.py_of(v);
    svg_line(out, p.left, y, p.left + p.width, y, kGridStyle);
    svg_text(out, p.left - 6, y + 4, fixed(v, decimals), "end", "class=\"ytick\" fill=\"#333\"");
  }
}

void svg_frame(std::string& out, const Panel& p, const std::string& x_title, const std::string& y_title) {
  out += "<rect x=\"" + px(p.left) + "\" y=\"" + px(p.top) + "\" width=\"" + px(p.width) + "\" height=\"" +
         px(p.height) + "\" fill=\"none\" stroke=\"#555\"/>\n";
  svg_text(out, p.left + p.width / 2, p.top + p.height + 33, html_escape(x_title), "middle",
           "font-weight=\"600\" fill=\"#222\"");
  const Real tx = p.left - 44, ty = p.top + p.height / 2;
  svg_text(out, tx, ty, html_escape(y_title), "middle",
           "font-weight=\"600\" fill=\"#222\" transform=\"rotate(-90 " + px(tx) + " " + px(ty) + ")\"");
}

void svg_axes(std::string& out, const Panel& p, const std::string& x_title, const std::string& y_title) {
  svg_x_ticks(out, p, ticks(p.x), tick_decimals(p.x.step));
  svg_y_ticks(out, p);
  svg_frame(out, p, x_title, y_title);
}

void svg_polyline(std::string& out, const std::vector<Point>& points, const std::string& colour) {
  if (points.size() < 2) return;
  out += "<polyline fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"1.4\" stroke-linejoin=\"round\" points=\"";
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i) out += ' ';
    out += px(points[i].x) + "," + px(points[i].y);
  }
  out += "\"/>\n";
}

std::string short_label(const std::string& text, std::size_t max_chars) {
  if (text.size() <= max_chars) return text;
  std::size_t cut = max_chars - 1;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
  return text.substr(0, cut) + "…";
}

Real text_width(const std::string& text) { return 6.2 * static_cast<Real>(text.size()); }

void svg_legend(std::string& out, Real x, Real y, const std::vector<LegendEntry>& entries, bool vertical) {
  for (const LegendEntry& e : entries) {
    const std::string label = short_label(e.label, 26);
    svg_line(out, x, y - 4, x + 22, y - 4,
             "stroke=\"" + e.colour + "\" stroke-width=\"2.5\"" + (e.dashed ? " stroke-dasharray=\"6 4\"" : ""));
    // A cut name keeps the whole one as a tooltip.
    const std::string tip = label == e.label ? "" : "<title>" + html_escape(e.label) + "</title>";
    svg_text(out, x + 28, y, tip + html_escape(label), "start", "fill=\"#222\"");
    if (vertical) {
      y += 18;
    } else {
      x += 28 + text_width(label) + 22;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Series

std::vector<std::size_t> minmax_indices(const std::vector<Real>& values, std::size_t max_points) {
  std::vector<std::size_t> out;
  const std::size_t n = values.size();
  if (n <= max_points) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(i);
    return out;
  }
  const std::size_t buckets = max_points / 2;
  const std::size_t size = (n + buckets - 1) / buckets;
  for (std::size_t start = 0; start < n; start += size) {
    const std::size_t end = std::min(n, start + size);
    std::size_t lo = start, hi = start;
    for (std::size_t i = start; i < end; ++i) {
      if (values[i] < values[lo]) lo = i;
      if (values[i] > values[hi]) hi = i;
    }
    out.push_back(std::min(lo, hi));
    if (lo != hi) out.push_back(std::max(lo, hi));
  }
  return out;
}

void svg_series(std::string& out, const Panel& p, const std::vector<Real>& time, const std::vector<Real>& values,
                const std::string& colour) {
  const std::size_t n = std::min(time.size(), values.size());
  const std::vector<Real> head(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n));
  std::vector<Point> points;
  for (const std::size_t i : minmax_indices(head, kMaxPoints)) points.push_back({p.px_of(time[i]), p.py_of(head[i])});
  svg_polyline(out, points, colour);
}

Real max_of(const std::vector<Real>& v) {
  Real m = 0;
  for (const Real x : v)
    if (std::isfinite(x)) m = std::max(m, x);
  return m;
}

}  // namespace svg
}  // namespace trocar
