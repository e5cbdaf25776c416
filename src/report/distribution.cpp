#include "src/report/parts.hpp"

#include "src/lot/statistics.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <cmath>

namespace allanlot::report {

using svg::escape;
using svg::number;

std::string distribution_plot(const std::string& id, const std::string& title,
                              const std::string& channel, const std::vector<Member>& members,
                              const std::vector<Outlier>& outliers) {
  svg::Plot p;
  p.id = id;
  p.title = title;
  p.x_scale = svg::Scale::Categorical;
  // Each term in its own datasheet unit: the axis is the ratio to the term's lot median, and the
  // median itself is printed with its unit under the term.
  p.y_label = "value / lot median (ratio)";
  p.x_label = "term, lot median and its unit";
  p.height = 330;
  p.width = 460;
  p.legend = false;
  svg::Series normal, out;
  normal.label = "unit (detected term)";
  normal.color = "#1f77b4";
  normal.line = false;
  normal.dots = true;
  normal.dot_size = 4;
  out.label = "outlier (links to the unit)";
  out.color = "#d62728";
  out.line = false;
  out.dots = true;
  out.dot_size = 6;
  for (std::size_t j = 0; j < kTerms.size(); ++j) {
    std::vector<std::pair<double, const Unit*>> v;
    std::string unit_ds;
    for (const Member& m : members) {
      if (!m.ch->fit) continue;
      const io::TermRecord* t = find_term(*m.ch->fit, kTerms[j].name);
      if (!t || !t->detected || !(t->value_datasheet > 0) || !std::isfinite(t->value_datasheet))
        continue;
      v.emplace_back(t->value_datasheet, m.unit);
      unit_ds = t->unit_datasheet;
    }
    std::string label = kTerms[j].name;
    if (v.empty()) {
      p.categories.push_back(label + "\nn.d.");
      continue;
    }
    std::vector<double> logs;
    for (const auto& [val, unit] : v)
      logs.push_back(std::log10(val));
    std::vector<double> sorted = logs;
    std::sort(sorted.begin(), sorted.end());
    const double med = lot::quantile_sorted(sorted, 0.5);
    const double median_value = std::pow(10.0, med);
    p.categories.push_back(label + "\n" + number(median_value, 3) + "\n" +
                           (unit_ds.empty() ? std::string("no units") : unit_ds));
    const double q1 = lot::quantile_sorted(sorted, 0.25), q3 = lot::quantile_sorted(sorted, 0.75);
    const double iqr = q3 - q1;
    double wlo = q1, whi = q3;
    for (const double l : sorted) {
      if (l >= q1 - 1.5 * iqr) wlo = std::min(wlo, l);
      if (l <= q3 + 1.5 * iqr) whi = std::max(whi, l);
    }
    const auto rel = [&](double l) { return std::pow(10.0, l - med); };
    p.boxes.push_back(
        {static_cast<double>(j), rel(q1), 1.0, rel(q3), rel(wlo), rel(whi), 0.28, "#555"});
    for (std::size_t i = 0; i < v.size(); ++i) {
      // Deterministic jitter (golden-ratio sequence) spreads the points of a term sideways.
      const double jitter =
          (std::fmod(0.5 + 0.6180339887 * static_cast<double>(i), 1.0) - 0.5) * 0.36;
      const double x = static_cast<double>(j) + jitter;
      const bool is_out = std::any_of(outliers.begin(), outliers.end(), [&](const Outlier& o) {
        return o.unit == v[i].second && o.channel == channel && o.term == j;
      });
      if (is_out) {
        out.x.push_back(x);
        out.y.push_back(rel(logs[i]));
        out.hrefs.push_back(channel_href(*v[i].second, channel));
        out.tooltips.push_back(v[i].second->rec.device_id + " " + kTerms[j].name + " = " +
                               number(v[i].first, 3) + " " + unit_ds);
      } else {
        normal.x.push_back(x);
        normal.y.push_back(rel(logs[i]));
      }
    }
  }
  if (p.boxes.empty()) return "";  // no term detected by any unit: no empty frame
  p.hlines.push_back({1.0, "#999", "4 3"});
  p.series.push_back(std::move(normal));
  if (!out.x.empty()) p.series.push_back(std::move(out));
  // At least a factor 2 either way, so that a tight lot does not look spread.
  std::vector<double> ys;
  for (const auto& s : p.series)
    ys.insert(ys.end(), s.y.begin(), s.y.end());
  for (const auto& b : p.boxes) {
    ys.push_back(b.whisker_lo);
    ys.push_back(b.whisker_hi);
  }
  double lo = 0.5, hi = 2.0;
  for (const double y : ys)
    if (std::isfinite(y) && y > 0) {
      lo = std::min(lo, y / 1.15);
      hi = std::max(hi, y * 1.15);
    }
  p.y_min = lo;
  p.y_max = hi;
  return svg::render(p);
}

}  // namespace allanlot::report
