#pragma once
/// What the assessment's HTML pages (report_html, learning_curve_html) share to draw their plots:
/// numbers as locale-free text, metric values in the unit a reader expects, "nice" axis scales,
/// inline-SVG primitives (axes, lines, polylines, legends), the palette and min/max thinning of
/// long series. Everything appends to a std::string and is deterministic byte for byte, so a
/// page is the same file on every machine. Text arguments named `escaped` must already be HTML
/// escaped; the others are escaped here.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// Escapes & < > " ' for HTML text and attributes (also declared in report_html.h, its public home).
std::string html_escape(std::string_view text);

/// Opens a self-contained page: doctype, `title`, the shared style (body, tables, pass/fail cells)
/// followed by the page's own `css`, then <body><main>.
void page_start(std::string& out, const std::string& title, const char* css);
/// Closes what page_start opened.
void page_end(std::string& out);

namespace svg {

// ---------------------------------------------------------------------------------------------
// Numbers as text

/// Fixed-point text with `decimals` digits, "–" for NaN or infinity, never "-0.00".
std::string fixed(Real v, int decimals);
/// Three significant digits, never in exponent notation.
std::string sig3(Real v);
/// An SVG coordinate (a tenth of a pixel).
std::string px(Real v);
/// "1 error", "3 errors".
std::string plural(int n, const char* one, const char* many);

/// How a metric's unit is shown: lengths in m switch to mm below 10 cm so that "0.01 m" does not
/// hide two digits; other units are shown as stated.
struct DisplayUnit {
  std::string unit;
  Real factor = 1;
  int decimals = -1;  ///< < 0: three significant digits
};

/// The display unit for values of `unit` up to `magnitude` (in that unit).
DisplayUnit display_unit(const std::string& unit, Real magnitude);
/// `v` (in the metric's unit) as text in `u`, without the unit.
std::string show(Real v, const DisplayUnit& u);
/// A spread (SD): keeps its own digits where the row's fixed decimals would say "0.00".
std::string show_spread(Real v, const DisplayUnit& u);

// ---------------------------------------------------------------------------------------------
// Colours: readable on white; red is kept for errors, thresholds and failing values.

inline constexpr const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd",
                                           "#8c564b", "#e377c2", "#17becf", "#7f7f00"};
inline constexpr std::size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];
inline constexpr const char* kRed = "#c62828";
inline constexpr const char* kGreen = "#1b7f3a";
inline constexpr const char* kGrey = "#8a8a8a";

/// The palette's i-th colour (wrapping), from the front or, `from_end`, from the back.
std::string palette_colour(std::size_t i, bool from_end = false);

// ---------------------------------------------------------------------------------------------
// Scales and panels

/// At most this many points per polyline: traces hold ~10^4 samples per series and a page must
/// stay small; 1500 points are finer than a plot's pixels.
inline constexpr std::size_t kMaxPoints = 1500;

/// An axis range; its ticks are lo, lo + step, … hi.
struct Scale {
  Real lo = 0, hi = 1, step = 1;
};

/// 1, 2 or 5 × 10^k near span / ticks: the step a reader interpolates between without effort.
Real nice_step(Real span, int ticks);
/// A range around [lo, hi] whose ends are multiples of a nice step, about `ticks` steps long.
Scale nice_scale(Real lo, Real hi, int ticks);
/// The tick values of `s` (an exact 0, never "-0").
std::vector<Real> ticks(const Scale& s);
/// Decimals that show every tick of a `step` exactly.
int tick_decimals(Real step);

/// A plot area in SVG pixels and the data ranges it maps.
struct Panel {
  Real left = 0, top = 0, width = 0, height = 0;
  Scale x, y;
  Real px_of(Real v) const { return left + (v - x.lo) / (x.hi - x.lo) * width; }
  Real py_of(Real v) const { return top + height - (v - y.lo) / (y.hi - y.lo) * height; }
};

// ---------------------------------------------------------------------------------------------
// SVG elements

/// `<svg id=… viewBox=…>` of `width` × `height` px; `label` is its accessible name. `id` is
/// written as given (pass an escaped one).
void svg_open(std::string& out, const std::string& id, int width, int height, const std::string& label);
void svg_text(std::string& out, Real x, Real y, const std::string& escaped, const char* anchor = "start",
              const std::string& extra = "");
/// `style`: the line's attributes ("stroke=… stroke-width=…").
void svg_line(std::string& out, Real x1, Real y1, Real x2, Real y2, const std::string& style);

/// A vertical grid line and a label below the panel at each of `values` (x data units).
void svg_x_ticks(std::string& out, const Panel& p, const std::vector<Real>& values, int decimals);
/// A horizontal grid line and a label left of the panel at each tick of p.y.
void svg_y_ticks(std::string& out, const Panel& p);
/// The panel's frame and the axis titles.
void svg_frame(std::string& out, const Panel& p, const std::string& x_title, const std::string& y_title);
/// Grid, frame, tick labels (at the ticks of both scales) and axis titles.
void svg_axes(std::string& out, const Panel& p, const std::string& x_title, const std::string& y_title);

struct Point {
  Real x = 0, y = 0;
};

/// One polyline through `points` (px); nothing for fewer than two.
void svg_polyline(std::string& out, const std::vector<Point>& points, const std::string& colour);

struct LegendEntry {
  std::string label;  ///< raw text (escaped when written)
  std::string colour;
  bool dashed = false;
};

/// `text` cut to `max_chars` bytes (whole UTF-8 characters) with "…", so a long name cannot run
/// over a plot.
std::string short_label(const std::string& text, std::size_t max_chars);
/// A rough width of 11 px sans text, enough to keep labels apart.
Real text_width(const std::string& text);
/// One swatch and label per entry, stacked (vertical) or in a row, starting at (x, y).
void svg_legend(std::string& out, Real x, Real y, const std::vector<LegendEntry>& entries, bool vertical);

// ---------------------------------------------------------------------------------------------
// Series

/// Sample indices of a series thinned to at most `max_points`: each bucket keeps its minimum and
/// maximum in order, so a short spike survives.
std::vector<std::size_t> minmax_indices(const std::vector<Real>& values, std::size_t max_points);
/// A time series as one polyline in `p`, thinned to kMaxPoints.
void svg_series(std::string& out, const Panel& p, const std::vector<Real>& time, const std::vector<Real>& values,
                const std::string& colour);
/// The largest finite value, at least 0.
Real max_of(const std::vector<Real>& v);

}  // namespace svg
}  // namespace trocar
