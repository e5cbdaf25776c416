#include "src/report/svg.hpp"

#include "src/report/svg_layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace allanlot::svg {

using layout::Axis;
using layout::coord;
using layout::Frame;
using layout::usable;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Coordinates with one decimal and no trailing ".0": a tenth of a viewBox pixel is below what
// any screen or printer shows, and short numbers keep a 500-unit report small.
void append_coord(std::string& out, double v) {
  v = std::clamp(v, -1e6, 1e6);
  const long long t = std::llround(v * 10.0);
  const long long a = t < 0 ? -t : t;
  char buf[32];
  if (a % 10 == 0)
    std::snprintf(buf, sizeof buf, "%s%lld", t < 0 ? "-" : "", a / 10);
  else
    std::snprintf(buf, sizeof buf, "%s%lld.%lld", t < 0 ? "-" : "", a / 10, a % 10);
  out += buf;
}

// Superscript markup for "10^k" style labels: the part after '^' is raised and smaller, with a
// true minus sign (U+2212), as typeset axes print it.
std::string tick_text(const std::string& label) {
  const auto caret = label.find('^');
  if (caret == std::string::npos) return escape(label);
  std::string exp = label.substr(caret + 1), shown;
  for (const char c : exp)
    shown += c == '-' ? std::string("\xE2\x88\x92") : std::string(1, c);
  return escape(label.substr(0, caret)) + "<tspan dy=\"-0.45em\" font-size=\"75%\">" + shown +
         "</tspan>";
}

// A label for d * 10^k (d in 1..9): decades as powers of ten on axes labelled by decades
// (the paper's figures); on narrow axes plain decimals for moderate exponents, else "d×10^k".
std::string mantissa_label(int d, int k, bool decades_only) {
  if (d == 1 && decades_only) return "10^" + std::to_string(k);
  if (k >= -3 && k <= 3) return number(d * std::pow(10.0, k), 6);
  if (d == 1) return "10^" + std::to_string(k);
  return std::to_string(d) +
         "\xC3\x97"
         "10^" +
         std::to_string(k);
}

// Padded data range of one axis; log axes snap to whole decades when the data span more than
// about a decade (the paper's figures), otherwise pad by a few percent so that the data do
// not touch the frame.
void auto_range(std::vector<double> v, Scale s, double& lo, double& hi) {
  std::erase_if(v, [s](double x) { return !usable(x, s); });
  const bool want_lo = std::isnan(lo), want_hi = std::isnan(hi);
  if (v.empty()) {
    if (want_lo) lo = s == Scale::Log ? 1.0 : 0.0;
    if (want_hi) hi = s == Scale::Log ? 10.0 : 1.0;
    return;
  }
  const auto [mn, mx] = std::minmax_element(v.begin(), v.end());
  double a = *mn, b = *mx;
  if (s == Scale::Log) {
    double la = std::log10(a), lb = std::log10(b);
    if (lb - la < 1e-9) {
      la -= 0.5;
      lb += 0.5;
    }
    const double pad = 0.04 * (lb - la);
    la -= pad;
    lb += pad;
    if (lb - la > 1.2) {
      la = std::floor(la + 1e-9);
      lb = std::ceil(lb - 1e-9);
    }
    if (want_lo) lo = std::pow(10.0, la);
    if (want_hi) hi = std::pow(10.0, lb);
  } else {
    if (b - a < 1e-300) {
      a -= 0.5;
      b += 0.5;
    }
    const double pad = 0.05 * (b - a);
    if (want_lo) lo = a - pad;
    if (want_hi) hi = b + pad;
  }
  if (!(hi > lo)) hi = s == Scale::Log ? lo * 10.0 : lo + 1.0;
}

void append_attr(std::string& out, const char* name, const std::string& value) {
  out += ' ';
  out += name;
  out += "=\"";
  out += value;
  out += '"';
}

}  // namespace

namespace layout {

std::string coord(double v) {
  std::string s;
  append_coord(s, v);
  return s;
}

}  // namespace layout

std::string escape(std::string_view text) {
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
      // Control characters are not allowed in XML 1.0 text; a corrupt name must not make the
      // page unreadable.
      if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t')
        out += '?';
      else
        out += c;
    }
  }
  return out;
}

std::string number(double v, int digits) {
  if (std::isnan(v)) return "-";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::vector<Tick> log_ticks(double lo, double hi) {
  std::vector<Tick> out;
  if (!(lo > 0) || !(hi > lo) || !std::isfinite(hi)) return out;
  const int k0 = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
  const int k1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
  const auto inside = [&](double v) { return v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9); };
  int decades_inside = 0;
  for (int k = k0; k <= k1; ++k)
    decades_inside += inside(std::pow(10.0, k)) ? 1 : 0;
  // Label every decade, every second one on a very wide axis; on a narrow axis (fewer than two
  // decades inside) also label 2 and 5, and on a very narrow one every mantissa, so that an
  // axis always carries at least two numbers.
  const int decade_step = decades_inside > 10 ? 2 : 1;
  int labelled_mantissa = 0;  // 0: decades only; 1: 1, 2, 5; 2: 1..9
  if (decades_inside < 2) {
    int n125 = 0;
    for (int k = k0; k <= k1; ++k)
      for (const int d : {1, 2, 5})
        n125 += inside(d * std::pow(10.0, k)) ? 1 : 0;
    labelled_mantissa = n125 >= 2 ? 1 : 2;
  }
  for (int k = k0; k <= k1; ++k)
    for (int d = 1; d <= 9; ++d) {
      const double v = d * std::pow(10.0, k);
      if (!inside(v)) continue;
      bool major = false;
      if (d == 1) major = labelled_mantissa > 0 || (k - k0) % decade_step == 0;
      if (labelled_mantissa == 1) major = major || d == 2 || d == 5;
      if (labelled_mantissa == 2) major = true;
      out.push_back(
          {v, major ? mantissa_label(d, k, labelled_mantissa == 0) : std::string(), major});
    }
  return out;
}

std::vector<Tick> linear_ticks(double lo, double hi) {
  std::vector<Tick> out;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return out;
  const double raw = (hi - lo) / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / mag;
  const double step = (r < 1.5 ? 1.0 : r < 3.5 ? 2.0 : r < 7.5 ? 5.0 : 10.0) * mag;
  for (double i = std::ceil(lo / step - 1e-9); i * step <= hi + 1e-9 * step; i += 1.0) {
    double v = i * step;
    if (std::abs(v) < 1e-12 * step) v = 0.0;
    out.push_back({v, number(v, 6), true});
  }
  return out;
}

Plot::Plot() : x_min(kNaN), x_max(kNaN), y_min(kNaN), y_max(kNaN) {}

namespace {

constexpr double kLegendFont = 11;  // px
constexpr double kLegendKey = 28;   // the line or swatch before an entry's text, with its gap

// `label` in lines of at most `max_w` px, broken at blanks (a word longer than that keeps a
// line of its own).
std::vector<std::string> wrap_text(const std::string& label, double max_w) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t start = 0;
  while (start <= label.size()) {
    auto end = label.find(' ', start);
    if (end == std::string::npos) end = label.size();
    const std::string word = label.substr(start, end - start);
    const std::string joined = line.empty() ? word : line + " " + word;
    if (!line.empty() && text_width(joined, kLegendFont) > max_w) {
      lines.push_back(line);
      line = word;
    } else {
      line = joined;
    }
    start = end + 1;
  }
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

void validate(const Plot& p) {
  if (p.id.empty()) throw std::invalid_argument("svg::render: empty plot id");
  for (const Series& s : p.series) {
    if (s.x.size() != s.y.size() || (!s.y_lo.empty() && s.y_lo.size() != s.y.size()) ||
        (!s.y_hi.empty() && s.y_hi.size() != s.y.size()) ||
        (!s.hrefs.empty() && s.hrefs.size() != s.y.size()) ||
        (!s.tooltips.empty() && s.tooltips.size() != s.y.size()))
      throw std::invalid_argument("svg::render: series '" + s.label + "' of plot '" + p.id +
                                  "' has vectors of different lengths");
  }
  for (const Band& b : p.bands)
    if (!b.vertical && (b.x.size() != b.lo.size() || b.x.size() != b.hi.size()))
      throw std::invalid_argument("svg::render: band of plot '" + p.id +
                                  "' has vectors of different lengths");
}

Frame frame_of(const Plot& p) {
  Frame f;
  Axis& xa = f.xa;
  Axis& ya = f.ya;
  // Ranges.
  xa.scale = p.x_scale == Scale::Categorical ? Scale::Linear : p.x_scale;
  ya.scale = p.y_scale == Scale::Categorical ? Scale::Linear : p.y_scale;
  std::vector<double> xs, ys;
  for (const Series& s : p.series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
    ys.insert(ys.end(), s.y_lo.begin(), s.y_lo.end());
    ys.insert(ys.end(), s.y_hi.begin(), s.y_hi.end());
  }
  for (const Band& b : p.bands) {
    xs.insert(xs.end(), b.x.begin(), b.x.end());
    ys.insert(ys.end(), b.lo.begin(), b.lo.end());
    ys.insert(ys.end(), b.hi.begin(), b.hi.end());
  }
  for (const Box& b : p.boxes) {
    ys.push_back(b.whisker_lo);
    ys.push_back(b.whisker_hi);
  }
  for (const HLine& h : p.hlines)
    ys.push_back(h.y);
  xa.lo = p.x_min;
  xa.hi = p.x_max;
  ya.lo = p.y_min;
  ya.hi = p.y_max;
  if (p.x_scale == Scale::Categorical) {
    const double n = static_cast<double>(std::max<std::size_t>(p.categories.size(), 1));
    if (std::isnan(xa.lo)) xa.lo = -0.5;
    if (std::isnan(xa.hi)) xa.hi = n - 0.5;
  } else {
    auto_range(xs, xa.scale, xa.lo, xa.hi);
  }
  auto_range(ys, ya.scale, ya.lo, ya.hi);

  // Layout: title above, tick labels and axis labels left and below, legend on the right.
  for (const Series& s : p.series)
    f.any_legend = f.any_legend || !s.label.empty();
  for (const Band& b : p.bands)
    f.any_legend = f.any_legend || !b.label.empty();
  f.any_legend = f.any_legend && p.legend;
  // Room under the plot for the tick labels (categorical ones may have several lines, 1.2em of
  // the 12 px font each) and the axis label.
  std::size_t lines = 1;
  for (const std::string& c : p.categories)
    lines = std::max<std::size_t>(lines, 1 + std::count(c.begin(), c.end(), '\n'));
  const double bottom = 50 + 14.4 * static_cast<double>(lines - 1);
  f.left = 78;
  f.top = p.title.empty() ? 14 : 34;
  // The legend column is as wide as its longest entry, up to 40 % of the plot; entries longer
  // than that wrap at blanks (never cut: a legend entry is the only key to its curve).
  if (f.any_legend) {
    double widest = 0;
    for (const Series& s : p.series)
      widest = std::max(widest, text_width(s.label, kLegendFont));
    for (const Band& b : p.bands)
      widest = std::max(widest, text_width(b.label, kLegendFont));
    f.legend_w = std::min(widest, 0.4 * p.width - kLegendKey - 22);
  }
  const double right = f.any_legend ? 14 + kLegendKey + f.legend_w + 8 : 16;
  f.plot_w = std::max(40.0, p.width - f.left - right);
  f.plot_h = std::max(40.0, p.height - f.top - bottom);
  f.xa.p0 = f.left;
  f.xa.p1 = f.left + f.plot_w;
  f.ya.p0 = f.top + f.plot_h;
  f.ya.p1 = f.top;
  return f;
}

struct Ticks {
  std::vector<Tick> x, y;
};

Ticks ticks_of(const Plot& p, const Frame& f) {
  // Grid and ticks.
  std::vector<Tick> xt;
  if (p.x_scale == Scale::Categorical) {
    for (std::size_t i = 0; i < p.categories.size(); ++i)
      xt.push_back({static_cast<double>(i), p.categories[i], true});
  } else {
    xt = f.x_log() ? log_ticks(f.xa.lo, f.xa.hi) : linear_ticks(f.xa.lo, f.xa.hi);
  }
  const std::vector<Tick> yt =
      f.y_log() ? log_ticks(f.ya.lo, f.ya.hi) : linear_ticks(f.ya.lo, f.ya.hi);
  return {std::move(xt), std::move(yt)};
}

// The grid lines (drawn now, under everything) and the tick marks (returned: drawn with the
// frame, over the data).
std::string draw_grid(std::string& o, const Plot& p, const Frame& f, const Ticks& ticks) {
  const std::vector<Tick>& xt = ticks.x;
  const std::vector<Tick>& yt = ticks.y;
  std::string grid_major, grid_minor, tick_marks;
  for (const Tick& t : xt) {
    if (p.x_scale == Scale::Categorical) continue;
    std::string& g = t.major ? grid_major : grid_minor;
    g += "M";
    append_coord(g, f.X(t.value));
    g += " ";
    append_coord(g, f.top);
    g += "V";
    append_coord(g, f.top + f.plot_h);
    tick_marks += "M";
    append_coord(tick_marks, f.X(t.value));
    tick_marks += " ";
    append_coord(tick_marks, f.top + f.plot_h);
    tick_marks += t.major ? "v6" : "v3";
  }
  for (const Tick& t : yt) {
    std::string& g = t.major ? grid_major : grid_minor;
    g += "M";
    append_coord(g, f.left);
    g += " ";
    append_coord(g, f.Y(t.value));
    g += "H";
    append_coord(g, f.left + f.plot_w);
    tick_marks += "M";
    append_coord(tick_marks, f.left);
    tick_marks += " ";
    append_coord(tick_marks, f.Y(t.value));
    tick_marks += t.major ? "h-6" : "h-3";
  }
  if (!grid_minor.empty())
    o += "<path d=\"" + grid_minor + "\" stroke=\"#eee\" stroke-width=\"1\" fill=\"none\"/>\n";
  if (!grid_major.empty())
    o += "<path d=\"" + grid_major + "\" stroke=\"#ccc\" stroke-width=\"1\" fill=\"none\"/>\n";

  return tick_marks;
}

// Bands, reference lines and boxes, under the series.
void draw_areas(std::string& o, const Plot& p, const Frame& f) {
  // Bands.
  for (const Band& b : p.bands) {
    std::string d;
    if (b.vertical) {
      if (b.x.size() < 2 || !f.ok_x(b.x[0]) || !f.ok_x(b.x[1])) continue;
      const double a = std::clamp(f.X(b.x[0]), f.left, f.left + f.plot_w);
      const double c = std::clamp(f.X(b.x[1]), f.left, f.left + f.plot_w);
      d = "M" + coord(a) + " " + coord(f.top) + "H" + coord(c) + "V" + coord(f.top + f.plot_h) +
          "H" + coord(a) + "Z";
    } else {
      // Upper edge left to right, lower edge back; runs of unusable points break the polygon.
      std::vector<std::size_t> idx;
      for (std::size_t i = 0; i < b.x.size(); ++i)
        if (f.ok_x(b.x[i]) && f.ok_y(b.lo[i]) && f.ok_y(b.hi[i])) idx.push_back(i);
      if (idx.size() < 2) continue;
      for (std::size_t j = 0; j < idx.size(); ++j) {
        d += j == 0 ? "M" : "L";
        d += coord(f.X(b.x[idx[j]])) + " " + coord(f.Y(b.hi[idx[j]]));
      }
      for (std::size_t j = idx.size(); j-- > 0;) {
        d += 'L';
        d += coord(f.X(b.x[idx[j]]));
        d += ' ';
        d += coord(f.Y(b.lo[idx[j]]));
      }
      d += "Z";
    }
    o += "<path d=\"" + d + "\" fill=\"" + escape(b.color) + "\" fill-opacity=\"" +
         number(b.opacity, 3) + "\" stroke=\"none\"/>\n";
  }
  for (const HLine& h : p.hlines) {
    if (!f.ok_y(h.y)) continue;
    o += "<path d=\"M" + coord(f.left) + " " + coord(f.Y(h.y)) + "H" + coord(f.left + f.plot_w) +
         "\" stroke=\"" + escape(h.color) + "\" stroke-width=\"1.2\"" +
         (h.dash.empty() ? std::string() : " stroke-dasharray=\"" + escape(h.dash) + "\"") +
         " fill=\"none\"/>\n";
  }
  for (const Box& b : p.boxes) {
    if (!f.ok_y(b.q1) || !f.ok_y(b.q3) || !f.ok_y(b.median)) continue;
    const double xl = f.X(b.x - b.half_width), xr = f.X(b.x + b.half_width), xc = f.X(b.x);
    const double cap = (xr - xl) / 4;
    std::string d = "M" + coord(xl) + " " + coord(f.Y(b.q3)) + "H" + coord(xr) + "V" +
                    coord(f.Y(b.q1)) + "H" + coord(xl) + "Z";
    if (f.ok_y(b.whisker_hi))
      d += "M" + coord(xc) + " " + coord(f.Y(b.q3)) + "V" + coord(f.Y(b.whisker_hi)) + "M" +
           coord(xc - cap) + " " + coord(f.Y(b.whisker_hi)) + "H" + coord(xc + cap);
    if (f.ok_y(b.whisker_lo))
      d += "M" + coord(xc) + " " + coord(f.Y(b.q1)) + "V" + coord(f.Y(b.whisker_lo)) + "M" +
           coord(xc - cap) + " " + coord(f.Y(b.whisker_lo)) + "H" + coord(xc + cap);
    o += "<path d=\"" + d + "\" stroke=\"" + escape(b.color) +
         "\" stroke-width=\"1.2\" fill=\"#f4f4f4\"/>\n";
    o += "<path d=\"M" + coord(xl) + " " + coord(f.Y(b.median)) + "H" + coord(xr) + "\" stroke=\"" +
         escape(b.color) + "\" stroke-width=\"2.4\"/>\n";
  }
}

// The classes of a series' <g> (and of its legend entry): its own, and "opt" when optional.
std::string series_class(const Series& s) {
  std::string c = escape(s.css_class);
  if (s.optional) c += c.empty() ? "opt" : " opt";
  return c;
}

// One series in its <g>: error bars, then the line, then dots (so that dots sit on top).
void draw_series_marks(std::string& o, const Series& s, const Frame& f);

void draw_series(std::string& o, const Series& s, const Frame& f) {
  const std::string cls = series_class(s);
  o += "<g class=\"series" + (cls.empty() ? std::string() : " " + cls) + "\"";
  if (!s.label.empty()) append_attr(o, "data-label", escape(s.label));
  o += ">\n";
  draw_series_marks(o, s, f);
  o += "</g>\n";
}

void draw_series_marks(std::string& o, const Series& s, const Frame& f) {
  const std::string color = escape(s.color);
  if (!s.y_lo.empty() && !s.y_hi.empty()) {
    std::string d;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!f.ok_x(s.x[i]) || !f.ok_y(s.y_lo[i]) || !f.ok_y(s.y_hi[i])) continue;
      const double x = f.X(s.x[i]), a = f.Y(s.y_lo[i]), b = f.Y(s.y_hi[i]);
      d += "M";
      append_coord(d, x);
      d += " ";
      append_coord(d, a);
      d += "V";
      append_coord(d, b);
      d += "M";
      append_coord(d, x - 2);
      d += " ";
      append_coord(d, a);
      d += "h4M";
      append_coord(d, x - 2);
      d += " ";
      append_coord(d, b);
      d += "h4";
    }
    if (!d.empty())
      o += "<path d=\"" + d + "\" stroke=\"" + color +
           "\" stroke-width=\"0.9\" stroke-opacity=\"0.7\" fill=\"none\"/>\n";
  }
  if (s.line) {
    std::string d;
    bool pen_down = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!f.ok_x(s.x[i]) || !f.ok_y(s.y[i])) {
        pen_down = false;
        continue;
      }
      d += pen_down ? " " : "M";
      append_coord(d, f.X(s.x[i]));
      d += " ";
      append_coord(d, f.Y(s.y[i]));
      pen_down = true;
    }
    if (!d.empty())
      o += "<path d=\"" + d + "\" stroke=\"" + color + "\" stroke-width=\"" + number(s.width, 3) +
           "\"" +
           (s.dash.empty() ? std::string() : " stroke-dasharray=\"" + escape(s.dash) + "\"") +
           " fill=\"none\" stroke-linejoin=\"round\"/>\n";
  }
  if (s.dots) {
    // Zero-length subpaths with round caps draw one dot per point in a single element.
    std::string d, links;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!f.ok_x(s.x[i]) || !f.ok_y(s.y[i])) continue;
      const double x = f.X(s.x[i]), y = f.Y(s.y[i]);
      if (!s.hrefs.empty() && !s.hrefs[i].empty()) {
        links += "<a href=\"" + escape(s.hrefs[i]) + "\"><circle cx=\"" + coord(x) + "\" cy=\"" +
                 coord(y) + "\" r=\"" + number(s.dot_size * 0.75, 3) + "\" fill=\"" + color +
                 "\" stroke=\"#000\" stroke-width=\"0.8\">";
        if (!s.tooltips.empty()) links += "<title>" + escape(s.tooltips[i]) + "</title>";
        links += "</circle></a>\n";
        continue;
      }
      d += "M";
      append_coord(d, x);
      d += " ";
      append_coord(d, y);
      d += "h0";
    }
    if (!d.empty())
      o += "<path d=\"" + d + "\" stroke=\"" + color + "\" stroke-width=\"" +
           number(s.dot_size, 3) + "\" stroke-linecap=\"round\" fill=\"none\"/>\n";
    o += links;
  }
}

void draw_axes(std::string& o, const Plot& p, const Frame& f, const Ticks& ticks,
               const std::string& tick_marks) {
  const std::vector<Tick>& xt = ticks.x;
  const std::vector<Tick>& yt = ticks.y;
  // Frame, ticks, tick labels.
  o += "<rect x=\"" + coord(f.left) + "\" y=\"" + coord(f.top) + "\" width=\"" + coord(f.plot_w) +
       "\" height=\"" + coord(f.plot_h) + "\" fill=\"none\" stroke=\"#333\" stroke-width=\"1\"/>\n";
  if (!tick_marks.empty())
    o += "<path d=\"" + tick_marks + "\" stroke=\"#333\" stroke-width=\"1\" fill=\"none\"/>\n";
  o += "<g fill=\"#222\">\n";
  for (const Tick& t : xt) {
    if (!t.major) continue;
    // Categorical labels may have several lines ('\n'), each centred under the category.
    const std::string x = coord(f.X(t.value));
    std::string text;
    std::size_t start = 0;
    for (int line = 0;; ++line) {
      const auto nl = t.label.find('\n', start);
      const std::string part = t.label.substr(start, nl == std::string::npos ? nl : nl - start);
      text += line == 0 ? tick_text(part)
                        : "<tspan x=\"" + x + "\" dy=\"1.2em\">" + tick_text(part) + "</tspan>";
      if (nl == std::string::npos) break;
      start = nl + 1;
    }
    o += "<text x=\"" + x + "\" y=\"" + coord(f.top + f.plot_h + 20) +
         "\" text-anchor=\"middle\">" + text + "</text>\n";
  }
  for (const Tick& t : yt) {
    if (!t.major) continue;
    o += "<text x=\"" + coord(f.left - 9) + "\" y=\"" + coord(f.Y(t.value) + 4) +
         "\" text-anchor=\"end\">" + tick_text(t.label) + "</text>\n";
  }
  o += "</g>\n";
  if (!p.x_label.empty())
    o += "<text x=\"" + coord(f.left + f.plot_w / 2) + "\" y=\"" + coord(p.height - 10) +
         "\" text-anchor=\"middle\" font-size=\"13\">" + escape(p.x_label) + "</text>\n";
  if (!p.y_label.empty())
    o += "<text transform=\"translate(16 " + coord(f.top + f.plot_h / 2) +
         ") rotate(-90)\" text-anchor=\"middle\" font-size=\"13\">" + escape(p.y_label) +
         "</text>\n";
  if (!p.title.empty())
    o += "<text x=\"" + coord(f.left) + "\" y=\"22\" font-size=\"14\" font-weight=\"bold\">" +
         escape(p.title) + "</text>\n";
}

// The legend entry's text: one <text>, a <tspan> per wrapped line.
std::string legend_text(const std::string& label, double x, double y, double max_w, int& n_lines) {
  const std::vector<std::string> lines = wrap_text(label, max_w);
  n_lines = static_cast<int>(lines.size());
  std::string o = "<text x=\"" + coord(x) + "\" y=\"" + coord(y) + "\">";
  for (std::size_t i = 0; i < lines.size(); ++i)
    o += i == 0 ? escape(lines[i])
                : "<tspan x=\"" + coord(x) + "\" dy=\"1.15em\">" + escape(lines[i]) + "</tspan>";
  return o + "</text>";
}

void draw_legend(std::string& o, const Plot& p, const Frame& f) {
  if (!f.any_legend) return;
  const double lx = f.left + f.plot_w + 14;
  double ly = f.top + 10;
  int n_lines = 1;
  o += "<g class=\"legend\" font-size=\"" + number(kLegendFont, 3) + "\">\n";
  for (const Band& b : p.bands) {
    if (b.label.empty()) continue;
    o += "<rect x=\"" + coord(lx) + "\" y=\"" + coord(ly - 6) + "\" width=\"22\" height=\"10\"" +
         " fill=\"" + escape(b.color) + "\" fill-opacity=\"" + number(b.opacity, 3) + "\"/>";
    o += legend_text(b.label, lx + kLegendKey, ly + 4, f.legend_w, n_lines) + "\n";
    ly += 17 + 13 * (n_lines - 1);
  }
  for (const Series& s : p.series) {
    if (s.label.empty()) continue;
    const std::string cls = series_class(s);
    o += cls.empty() ? "<g>" : "<g class=\"" + cls + "\">";
    if (s.line)
      o += "<path d=\"M" + coord(lx) + " " + coord(ly) + "h22\" stroke=\"" + escape(s.color) +
           "\" stroke-width=\"" + number(std::max(s.width, 1.5), 3) + "\"" +
           (s.dash.empty() ? std::string() : " stroke-dasharray=\"" + escape(s.dash) + "\"") + "/>";
    if (s.dots)
      o += "<path d=\"M" + coord(lx + 11) + " " + coord(ly) + "h0\" stroke=\"" + escape(s.color) +
           "\" stroke-width=\"" + number(s.dot_size + 1, 3) + "\" stroke-linecap=\"round\"/>";
    o += legend_text(s.label, lx + kLegendKey, ly + 4, f.legend_w, n_lines) + "</g>\n";
    ly += 17 + 13 * (n_lines - 1);
  }
  o += "</g>\n";
}

}  // namespace

std::string render(const Plot& p) {
  validate(p);
  const Frame f = frame_of(p);
  std::string o;
  o.reserve(8192);
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\"";
  append_attr(o, "id", escape(p.id));
  append_attr(o, "class", "plot");
  o += " viewBox=\"0 0 " + coord(p.width) + " " + coord(p.height) + "\"";
  o += " font-family=\"Helvetica,Arial,sans-serif\" font-size=\"12\" role=\"img\"";
  append_attr(o, "aria-label", escape(p.title));
  o += ">\n";
  if (!p.title.empty()) o += "<title>" + escape(p.title) + "</title>\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n";
  const std::string clip = escape(p.id) + "-clip";
  o += "<clipPath id=\"" + clip + "\"><rect x=\"" + coord(f.left) + "\" y=\"" + coord(f.top) +
       "\" width=\"" + coord(f.plot_w) + "\" height=\"" + coord(f.plot_h) + "\"/></clipPath>\n";

  const Ticks ticks = ticks_of(p, f);
  const std::string tick_marks = draw_grid(o, p, f, ticks);
  o += "<g clip-path=\"url(#" + clip + ")\">\n";
  draw_areas(o, p, f);
  for (const Series& s : p.series)
    draw_series(o, s, f);
  o += "</g>\n";
  layout::draw_annotations(o, p, f);
  draw_axes(o, p, f, ticks, tick_marks);
  draw_legend(o, p, f);
  o += "</svg>\n";
  return o;
}

}  // namespace allanlot::svg
