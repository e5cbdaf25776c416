// A small SVG plotting module for the HTML report: log-log (or linear, or categorical) axes
// with decade ticks, lines, dots, error bars, shaded bands, asymptote lines with text labels,
// box plots and a legend, rendered to one self-contained <svg> element.
//
// Why our own: the report must need nothing installed (no Python, no gnuplot, no JavaScript)
// and must be byte-for-byte deterministic, and plots of Allan curves need only a handful of
// primitives. Sizes matter too (a lot of 500 units holds thousands of plots), so each series
// is drawn as a single <path>: a line is one "M ... L ..." path, dots are zero-length
// subpaths with round caps, error bars are vertical subpaths; coordinates are printed with
// one decimal (a tenth of a pixel of the viewBox, invisible at any zoom a reader uses).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace allanlot::svg {

/// Escapes the five XML special characters, so that any text (a device id, a unit string, a
/// file name) can go into SVG/HTML text or a quoted attribute.
std::string escape(std::string_view text);

/// Formats `v` with `digits` significant digits, like printf("%.*g"), and "-" for NaN.
std::string number(double v, int digits = 3);

enum class Scale {
  Log,         // base-10 logarithmic: ticks at decades, minor ticks at 2..9
  Linear,      // ticks at 1, 2 or 5 times a power of ten
  Categorical  // x only: categories 0 .. n-1 at integer positions, labelled by `categories`
};

/// One data series. Points whose x or y cannot be shown (not finite, or <= 0 on a log axis)
/// are skipped, and a line is broken there rather than joined across.
struct Series {
  std::string label;                  // legend entry ("" = not in the legend)
  std::string color = "#1f77b4";      // any CSS colour
  std::vector<double> x, y;           // data coordinates
  std::vector<double> y_lo, y_hi;     // error bars (empty = none); same length as y
  bool line = true;                   // join the points
  bool dots = false;                  // a dot at every point
  double width = 1.5;                 // line width (px of the viewBox)
  double dot_size = 4.0;              // dot diameter
  std::string dash;                   // SVG stroke-dasharray, e.g. "6 4" ("" = solid)
  std::vector<std::string> hrefs;     // per point: a link for the dot ("" = none); empty = none
  std::vector<std::string> tooltips;  // per point: text shown on hover with its link
  // Classes of the <g> that holds the series and its legend entry, e.g. "s-mdev": the page's
  // CSS can show or hide a series by them. `optional` series get the class "opt" too (the page
  // hides them until the reader ticks their box) and labels do not avoid them.
  std::string css_class = "";
  bool optional = false;
};

/// Text placed at data coordinates (clamped into the plot area so it is never lost).
struct Annotation {
  double x = 0, y = 0;
  std::string text;
  std::string color = "#333";
  std::string anchor = "start";  // SVG text-anchor: start, middle, end
  double dx = 4, dy = -4;        // offset from the point in px
  // Placed near (x, y) but clear of the marks of the plot's non-optional series and of the
  // labels placed before it (a label on a curve hides both), with a leader line when moved far.
  bool avoid = false;
  std::string css_class = "";  // class of the <text>, e.g. "slope"
};

/// A shaded area between two curves over x (e.g. a Monte Carlo band), or, with `vertical`
/// set, a shaded x-interval over the whole height (e.g. a validity range: uses x[0], x[1]).
struct Band {
  std::vector<double> x, lo, hi;
  std::string color = "#1f77b4";
  double opacity = 0.15;
  bool vertical = false;
  std::string label;  // legend entry ("" = none)
};

/// A box plot at a category: quartiles, median and whiskers (in data coordinates).
struct Box {
  double x = 0;  // category position
  double q1 = 0, median = 0, q3 = 0, whisker_lo = 0, whisker_hi = 0;
  double half_width = 0.25;  // in category units
  std::string color = "#555";
};

/// A horizontal reference line across the plot (e.g. ratio = 1).
struct HLine {
  double y = 1;
  std::string color = "#888";
  std::string dash = "4 3";
};

struct Plot {
  std::string id;     // unique in the HTML page; used for the element id and clip path
  std::string title;  // above the plot
  std::string x_label, y_label;
  Scale x_scale = Scale::Log, y_scale = Scale::Log;
  std::vector<std::string> categories;  // x labels for Scale::Categorical
  // Axis ranges; NaN = from the data (log axes: padded, and snapped to whole decades when the
  // data span more than about one decade, as the paper's figures are).
  double x_min, x_max, y_min, y_max;
  double width = 720, height = 420;  // viewBox size in px; CSS scales the element
  bool legend = true;       // legend to the right of the plot area, as wide as its longest entry
  std::vector<Band> bands;  // drawn first
  std::vector<HLine> hlines;
  std::vector<Box> boxes;
  std::vector<Series> series;  // in order; the legend follows this order
  std::vector<Annotation> annotations;
  Plot();
};

/// Renders `p` as one <svg> element (no XML declaration: it is meant to be inlined in HTML).
/// Deterministic: the same plot gives the same bytes. Throws std::invalid_argument when a
/// series' vectors have different lengths or the id is empty.
std::string render(const Plot& p);

/// Axis ticks, exposed for tests: the values of the major (labelled) ticks of a log axis over
/// [lo, hi] (lo > 0) and their labels, e.g. 1e-3 -> "10^-3" rendered with a superscript.
struct Tick {
  double value = 0;
  std::string label;  // plain text form, e.g. "10^-3", "0.5", "2"
  bool major = true;  // major ticks are labelled; minor ones are short and unlabelled
};
std::vector<Tick> log_ticks(double lo, double hi);
/// A generous estimate of the width in px of `text` at `font_px` in the report's sans-serif
/// fonts (Helvetica, Arial or the DejaVu Sans that stands in for them, the widest): legends
/// and labels are laid out with it, so that none is cut or runs off the plot.
double text_width(std::string_view text, double font_px);
std::vector<Tick> linear_ticks(double lo, double hi);

}  // namespace allanlot::svg
