// A channel's data editing in the report (docs/reports.md, docs/editing.md): the drift removed
// with its residual plot, the list of edits, and the dynamic Allan deviation as a heat map.
#include "src/report/parts.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace allanlot::report {

using svg::escape;
using svg::number;

namespace {

// Rows of the edits table shown; the rest are counted (the results file lists them all).
constexpr std::size_t kEditRows = 40;

std::string drift_part(const std::string& id, const io::DriftRecord& d) {
  std::ostringstream h;
  h << "<div class=\"fig\"><h4>Drift removed (" << escape(d.model) << ", fitted to the "
    << escape(d.fitted_to)
    << ")</h4>\n<table><tr><th>parameter</th><th>value</th><th>sigma</th><th>unit</th></tr>\n";
  for (std::size_t i = 0; i < d.parameter.size() && i < d.value.size(); ++i)
    h << "<tr><td>" << escape(d.parameter[i]) << "</td><td>" << number(d.value[i], 6) << "</td><td>"
      << (i < d.sigma.size() ? number(d.sigma[i], 2) : "-") << "</td><td>"
      << (i < d.unit.size() ? escape(d.unit[i]) : "") << "</td></tr>\n";
  h << "</table>\n";
  if (!d.t.empty()) {
    svg::Plot p;
    p.id = id + "-drift";
    p.title = "Residuals against the drift model (block means)";
    p.x_label = "t (s)";
    p.y_label = d.fitted_to == "phase" ? "phase residual" : "frequency residual";
    p.x_scale = svg::Scale::Linear;
    p.y_scale = svg::Scale::Linear;
    p.legend = false;
    p.height = 300;
    svg::Series s;
    s.x = d.t;
    s.y = d.residual;
    p.series.push_back(std::move(s));
    p.hlines.push_back({0.0, "#888", "4 3"});
    h << svg::render(p) << "\n";
  }
  h << "</div>\n";
  return h.str();
}

std::string edits_part(const std::vector<io::EditRecord>& edits) {
  std::ostringstream h;
  h << "<div><h4>Edits (" << edits.size()
    << ", samples made missing; the original recording is unchanged)</h4>\n<table><tr><th>kind"
       "</th><th>samples</th><th>time (s)</th><th>value removed</th><th>robust &sigma;</th></tr>\n";
  for (std::size_t i = 0; i < edits.size() && i < kEditRows; ++i) {
    const io::EditRecord& e = edits[i];
    h << "<tr><td>" << escape(e.kind) << "</td><td>" << e.first;
    if (e.last != e.first) h << "&ndash;" << e.last;
    h << "</td><td>" << number(e.t_start, 6);
    if (e.last != e.first) h << "&ndash;" << number(e.t_end, 6);
    h << "</td><td>" << number(e.value, 6) << "</td><td>" << number(e.sigmas, 3) << "</td></tr>\n";
  }
  h << "</table>\n";
  if (edits.size() > kEditRows)
    h << "<p class=\"small\">and " << edits.size() - kEditRows
      << " more, listed in the results file's edits/ group</p>\n";
  h << "</div>\n";
  return h.str();
}

// A colour from dark blue through green to yellow for u in [0, 1] (viridis' ends and middle,
// interpolated linearly), so that the heat map reads in grey too.
std::string heat_color(double u) {
  static const double stops[3][3] = {{68, 1, 84}, {33, 145, 140}, {253, 231, 37}};
  u = std::clamp(u, 0.0, 1.0) * 2;
  const int k = std::min(static_cast<int>(u), 1);
  const double f = u - k;
  char c[8];
  std::snprintf(c, sizeof c, "#%02x%02x%02x",
                static_cast<int>(std::lround(stops[k][0] + f * (stops[k + 1][0] - stops[k][0]))),
                static_cast<int>(std::lround(stops[k][1] + f * (stops[k + 1][1] - stops[k][1]))),
                static_cast<int>(std::lround(stops[k][2] + f * (stops[k + 1][2] - stops[k][2]))));
  return c;
}

// log10 of each value over the median of its row (its tau) across the windows: what changes
// along the record, which the fall of the deviation with tau would otherwise drown. NaN where
// the window has no value.
std::vector<double> relative_to_row_median(const io::DynamicRecord& d) {
  const std::size_t nw = d.t_center.size(), nt = d.tau.size();
  std::vector<double> rel(d.oadev.size(), kNaN);
  for (std::size_t j = 0; j < nt; ++j) {
    std::vector<double> row;
    for (std::size_t w = 0; w < nw; ++w)
      if (const double v = d.oadev[w * nt + j]; std::isfinite(v) && v > 0) row.push_back(v);
    if (row.empty()) continue;
    std::nth_element(row.begin(), row.begin() + static_cast<std::ptrdiff_t>(row.size() / 2),
                     row.end());
    const double median = row[row.size() / 2];
    for (std::size_t w = 0; w < nw; ++w)
      if (const double v = d.oadev[w * nt + j]; std::isfinite(v) && v > 0)
        rel[w * nt + j] = std::log10(v / median);
  }
  return rel;
}

// The heat map: one column per window (time), one row per tau (the shortest at the bottom),
// the colour each deviation relative to its tau's median over the windows, on a log scale
// symmetric about 1.
std::string dynamic_part(const std::string& id, const io::DynamicRecord& d) {
  const std::size_t nw = d.t_center.size(), nt = d.tau.size();
  if (nw == 0 || nt == 0 || d.oadev.size() != nw * nt) return "";
  const std::vector<double> rel = relative_to_row_median(d);
  double span = 0;
  for (const double r : rel)
    if (std::isfinite(r)) span = std::max(span, std::abs(r));
  span = std::max(span, 1e-3);
  constexpr double left = 90, top = 30, width = 540, height = 260;
  const double cw = width / static_cast<double>(nw), rh = height / static_cast<double>(nt);
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << escape(id)
    << "-dyn\" class=\"plot\" viewBox=\"0 0 760 340\" font-family=\"Helvetica,Arial,"
    << "sans-serif\" font-size=\"12\" role=\"img\" shape-rendering=\"crispEdges\">"
    << "<title>Dynamic Allan deviation</title>\n<text x=\"" << left
    << "\" y=\"18\">Dynamic Allan deviation over its median at each tau (window " << d.window
    << " samples, step " << d.step << ")</text>\n";
  for (std::size_t w = 0; w < nw; ++w)
    for (std::size_t j = 0; j < nt; ++j) {
      const double r = rel[w * nt + j];
      if (!std::isfinite(r)) continue;
      s << "<rect x=\"" << number(left + cw * static_cast<double>(w), 5) << "\" y=\""
        << number(top + height - rh * static_cast<double>(j + 1), 5) << "\" width=\""
        << number(cw + 0.05, 4) << "\" height=\"" << number(rh + 0.05, 4) << "\" fill=\""
        << heat_color((r / span + 1) / 2) << "\"/>\n";
    }
  const auto label = [&](double x, double y, const std::string& t, const char* anchor) {
    s << "<text x=\"" << number(x, 5) << "\" y=\"" << number(y, 5) << "\" text-anchor=\"" << anchor
      << "\">" << escape(t) << "</text>\n";
  };
  label(left - 4, top + height - rh / 2 + 4, "\xCF\x84 " + number(d.tau.front(), 3) + " s", "end");
  label(left - 4, top + rh / 2 + 4, "\xCF\x84 " + number(d.tau.back(), 3) + " s", "end");
  label(left, top + height + 16, number(d.t_center.front(), 4) + " s", "start");
  label(left + width, top + height + 16, number(d.t_center.back(), 4) + " s", "end");
  label(left + width / 2, top + height + 34, "window centre; rows: \xCF\x84 in octaves", "middle");
  // The colour scale: the deviation as a multiple of its tau's median.
  for (int k = 0; k < 20; ++k)
    s << "<rect x=\"650\" y=\"" << number(top + height - (k + 1) * height / 20, 5)
      << "\" width=\"16\" height=\"" << number(height / 20 + 0.05, 4) << "\" fill=\""
      << heat_color((k + 0.5) / 20) << "\"/>\n";
  label(672, top + 10, "\xC3\x97" + number(std::pow(10.0, span), 3), "start");
  label(672, top + height / 2 + 4,
        "\xC3\x97"
        "1 (median)",
        "start");
  label(672, top + height, "\xC3\x97" + number(std::pow(10.0, -span), 3), "start");
  s << "</svg>\n";
  return "<div class=\"fig\"><h4>Dynamic Allan deviation</h4>\n" + s.str() + "</div>\n";
}

}  // namespace

std::string editing_section(const std::string& id, const io::ChannelResult& ch) {
  if (!ch.drift && ch.edits.empty() && !ch.dynamic) return "";
  std::string h = "<div class=\"tables\">\n";
  if (ch.drift) h += drift_part(id, *ch.drift);
  if (!ch.edits.empty()) h += edits_part(ch.edits);
  if (ch.dynamic) h += dynamic_part(id, *ch.dynamic);
  return h + "</div>\n";
}

}  // namespace allanlot::report
