// The report's clock parts (docs/reports.md "Clocks: the hat and ITU-T masks"): the section of a
// hat's results (each clock's Allan deviation with its interval, in one plot and one table) and
// the ITU-T masks a spec applies to a channel, drawn on its time-error plot.
#include "src/report/parts.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

namespace allanlot::report {

using svg::escape;
using svg::number;

namespace {

constexpr const char* kClockColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                        "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

std::string root_attribute(const io::RecordingResult& r, const std::string& key) {
  for (const auto& [k, v] : r.attributes)
    if (k == key) return v;
  return "";
}

// The clocks' OADEV: every /clocks/<name> channel, in file order.
std::vector<std::pair<std::string, const kernels::StatResult*>>
clock_curves(const io::RecordingResult& r) {
  std::vector<std::pair<std::string, const kernels::StatResult*>> out;
  for (const io::ChannelResult& ch : r.channels)
    if (ch.path.starts_with("/clocks/") && !ch.stats.empty())
      out.emplace_back(ch.path.substr(8), &ch.stats.front().second);
  return out;
}

std::string hat_plot(const std::string& id,
                     const std::vector<std::pair<std::string, const kernels::StatResult*>>& c) {
  svg::Plot p;
  p.id = id;
  p.title = "Each clock's Allan deviation (" + std::to_string(c.size()) + "-cornered hat)";
  p.x_label = "\xCF\x84 (s)";
  p.y_label = "\xCF\x83y(\xCF\x84)";
  std::vector<double> taus, ys;
  for (std::size_t k = 0; k < c.size(); ++k) {
    svg::Series se;
    se.label = "clock " + c[k].first;
    se.color = kClockColors[k % std::size(kClockColors)];
    se.dots = true;
    const kernels::StatResult& s = *c[k].second;
    // Only the positive estimates: a negative variance has no place on a log axis (the table
    // gives it).
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!(s.dev[i] > 0.0)) continue;
      se.x.push_back(s.tau_s[i]);
      se.y.push_back(s.dev[i]);
      se.y_lo.push_back(s.dev_lo[i]);
      se.y_hi.push_back(s.dev_hi[i]);
      taus.push_back(s.tau_s[i]);
      ys.insert(ys.end(), {s.dev[i], s.dev_lo[i], s.dev_hi[i]});
    }
    if (s.confidence > 0) se.label += " (bars: " + number(100 * s.confidence, 3) + " % CI)";
    p.series.push_back(std::move(se));
  }
  if (taus.empty()) return "";
  std::tie(p.x_min, p.x_max) = decade_range(taus);
  std::tie(p.y_min, p.y_max) = decade_range(ys);
  return "<div class=\"panel\">\n" + svg::render(p) + "</div>\n";
}

std::string hat_table(const std::vector<std::pair<std::string, const kernels::StatResult*>>& c) {
  std::ostringstream h;
  h << "<table class=\"dev\"><caption>Each clock's Allan deviation and its interval</caption>\n"
       "<tr><th>&tau; (s)</th>";
  for (const auto& [name, s] : c)
    h << "<th>" << escape(name) << " lower</th><th>" << escape(name) << "</th><th>" << escape(name)
      << " upper</th>";
  h << "</tr>\n";
  const kernels::StatResult& first = *c.front().second;
  for (std::size_t i = 0; i < first.size(); ++i) {
    h << "<tr><td>" << cell_number(first.tau_s[i], 4) << "</td>";
    for (const auto& [name, s] : c) {
      const bool row = i < s->size();
      h << "<td>" << (row ? number(s->dev_lo[i], 4) : "") << "</td><td"
        << (row && s->dev[i] < 0.0 ? " class=\"bad\"" : "") << ">"
        << (row ? number(s->dev[i], 4) : "") << "</td><td>" << (row ? number(s->dev_hi[i], 4) : "")
        << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

}  // namespace

std::string hat_section(const Unit& u) {
  if (root_attribute(u.rec, "statistic") != "hat") return "";
  const auto c = clock_curves(u.rec);
  if (c.empty()) return "";
  std::ostringstream h;
  h << "<section class=\"hat\" id=\"" << u.anchor << "-hat\">\n<h3>Clocks by the " << c.size()
    << "-cornered hat</h3>\n<p class=\"small\">Each clock's overlapping Allan "
       "deviation from the pairs' (the least-squares solution of the pairs' variances, with "
       "intervals from their equivalent degrees of freedom: docs/hat-and-masks.md). A negative "
       "deviation (red in the table) is a negative variance estimate, reported as it is and left "
       "off the plot.</p>\n"
    << hat_plot(u.anchor + "-hat-plot", c) << hat_table(c) << "</section>\n";
  return h.str();
}

void add_mask_series(svg::Plot& p, const std::vector<const masks::Mask*>& ms, double factor) {
  for (const masks::Mask* m : ms) {
    svg::Series se;
    se.label = std::string(m->name) + " " + (m->stat == "mtie" ? "MTIE" : "TDEV") + " mask";
    se.color = m->stat == "mtie" ? "#7f7f7f" : "#000000";
    se.dash = m->stat == "mtie" ? "2 3" : "6 4";
    se.width = 1.2;
    // MTIE is behind a tick box on the time-error plot: its mask shows and hides with it.
    if (m->stat == "mtie") {
      se.css_class = "s-mtie";
      se.optional = true;
    }
    const double lo = masks::first_tau_s(*m), hi = masks::last_tau_s(*m);
    for (int k = 0; k <= 60; ++k) {
      const double tau = lo * std::pow(hi / lo, k / 60.0);
      se.x.push_back(tau);
      se.y.push_back(masks::limit_s(*m, std::min(tau, hi)) * factor);
    }
    p.series.push_back(std::move(se));
  }
}

}  // namespace allanlot::report
