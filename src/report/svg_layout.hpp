// The layout of a plot that the files of src/report/svg*.cpp share: its axes and frame in
// viewBox pixels, and the placement of labels clear of the curves (svg_labels.cpp). Internal to
// the SVG module (src/report/svg.hpp).
#pragma once

#include "src/report/svg.hpp"

#include <cmath>
#include <string>

namespace allanlot::svg::layout {

// Whether `v` can be drawn on an axis of scale `s` (a log axis has no zero or negatives).
inline bool usable(double v, Scale s) {
  return std::isfinite(v) && (s != Scale::Log || v > 0.0);
}

struct Axis {
  Scale scale = Scale::Log;
  double lo = 1, hi = 10;  // data range shown
  double p0 = 0, p1 = 1;   // pixel positions of lo and hi
  double t(double v) const { return scale == Scale::Log ? std::log10(v) : v; }
  double px(double v) const { return p0 + (t(v) - t(lo)) / (t(hi) - t(lo)) * (p1 - p0); }
};

// The plot area and the two axes of a plot, in viewBox pixels.
struct Frame {
  Axis xa, ya;
  double left = 78, top = 14, plot_w = 40, plot_h = 40;
  bool any_legend = false;
  double legend_w = 0;  // width of the legend's text column
  double X(double v) const { return xa.px(v); }
  double Y(double v) const { return ya.px(v); }
  bool ok_x(double v) const { return usable(v, xa.scale); }
  bool ok_y(double v) const { return usable(v, ya.scale); }
  bool x_log() const { return xa.scale == Scale::Log; }
  bool y_log() const { return ya.scale == Scale::Log; }
};

// A number as a coordinate: one decimal, no trailing ".0".
std::string coord(double v);

// The annotations of `p`; those with `avoid` set away from the marks of its non-optional series
// and from each other.
void draw_annotations(std::string& o, const Plot& p, const Frame& f);

}  // namespace allanlot::svg::layout
