// A clock channel as metrologists read it (docs/clocks.md "The clock report"): the power-law
// levels with their noise types' names, the power-law model on the Allan plot, the deviations
// against that model, and the lot page's table of each clock's levels, never pooled into one
// distribution.
#include "src/report/parts.hpp"

#include "kernels/powerlaw/names.hpp"
#include "kernels/powerlaw/theory.hpp"
#include "src/report/svg.hpp"

#include <cmath>
#include <sstream>
#include <tuple>

namespace allanlot::report {

using svg::escape;
using svg::number;

namespace {

namespace pl = kernels::powerlaw;

// Distinct colours of the five noise types' asymptotes.
const char* level_color(std::int64_t alpha) {
  switch (alpha) {
  case 2:
    return "#7f7f7f";
  case 1:
    return "#8c564b";
  case 0:
    return "#17becf";
  case -1:
    return "#bcbd22";
  default:
    return "#ff7f0e";
  }
}

// The Allan deviation slope mu (sigma ~ tau^mu) of each noise type (SP1065 sec. 5.2.4).
const char* level_slope(std::int64_t alpha) {
  switch (alpha) {
  case 2:
  case 1:
    return "\xE2\x88\x92"
           "1";
  case 0:
    return "\xE2\x88\x92"
           "1/2";
  case -1:
    return "0";
  default:
    return "+1/2";
  }
}

// "h +- sigma" when detected, "< upper" when not.
std::string level_cell(const io::PowerLawLevelRecord& l) {
  return l.detected ? value_pm(l.h, l.h_sigma) : "&lt; " + cell_number(l.h_upper, 2);
}

bool fitted(const io::ChannelResult& ch) {
  return ch.powerlaw && ch.powerlaw->status == "ok" && ch.sample_rate_hz > 0;
}

}  // namespace

bool is_clock_channel(const io::ChannelResult& ch) {
  return pl::is_clock_channel(ch.units, ch.data_type);
}

std::string noise_type_label(int alpha) {
  const std::string_view name = pl::noise_type_name_long(alpha);
  return std::to_string(alpha) + (name.empty() ? "" : " (" + std::string(name) + ")");
}

std::string powerlaw_table_html(const io::ChannelResult& ch) {
  if (!ch.powerlaw) return "";
  const io::PowerLawRecord& p = *ch.powerlaw;
  std::ostringstream h;
  h << "<table class=\"coef\"><tr><th class=\"l\">noise type</th><th>&alpha;</th><th>ADEV slope "
       "&mu;</th><th>h<sub>&alpha;</sub> &plusmn; 1&sigma;</th><th class=\"l\">unit</th>"
       "<th>detected<br><span class=\"small\">else 95 % upper bound</span></th></tr>\n";
  for (const io::PowerLawLevelRecord& l : p.levels)
    h << "<tr><td class=\"l\"><b>" << escape(l.name) << "</b></td><td>" << l.alpha << "</td><td>"
      << level_slope(l.alpha) << "</td><td" << (l.detected ? "" : " class=\"nd\"") << ">"
      << value_pm(l.h, l.h_sigma) << "</td><td class=\"l\">Hz<sup>" << -1 - l.alpha
      << "</sup></td><td>"
      << (l.detected ? std::string("yes")
                     : "<span class=\"nd\">no, &lt; " + cell_number(l.h_upper, 2) + "</span>")
      << "</td></tr>\n";
  h << "</table>\n<p class=\"small\">S<sub>y</sub>(f) = &Sigma; h<sub>&alpha;</sub> "
       "f<sup>&alpha;</sup> of the fractional frequency (NIST SP1065 sec. 5.1), fitted to OADEV "
       "and MDEV at once; status "
    << escape(p.status) << ".</p>\n";
  return h.str();
}

void add_powerlaw(svg::Plot& p, const io::ChannelResult& ch, double factor) {
  if (!fitted(ch)) return;
  const io::PowerLawRecord& pr = *ch.powerlaw;
  const double tau0 = 1.0 / ch.sample_rate_hz;
  svg::Series model;
  model.label = "power-law model";
  model.color = "#000";
  model.width = 2.0;
  model.css_class = "fit";
  model.x = pr.tau;
  for (const double v : pr.adev_model)
    model.y.push_back(v * factor);
  p.series.push_back(std::move(model));
  for (const io::PowerLawLevelRecord& l : pr.levels) {
    if (!l.detected || !(l.h > 0)) continue;
    svg::Series a;
    a.label = l.name + ": slope " + level_slope(l.alpha);
    a.color = level_color(l.alpha);
    a.dash = "7 4";
    a.width = 1.4;
    a.css_class = "term";
    // Over the taus fitted: flicker PM's slope is -1 only up to its logarithm.
    for (const double x : pr.tau) {
      a.x.push_back(x);
      a.y.push_back(std::sqrt(l.h * pl::avar_per_h(static_cast<int>(l.alpha), x, tau0)) * factor);
    }
    p.series.push_back(std::move(a));
  }
}

std::string powerlaw_residual_plot(const std::string& id, const io::ChannelResult& ch) {
  if (!fitted(ch)) return "";
  const io::PowerLawRecord& pr = *ch.powerlaw;
  svg::Plot p;
  p.id = id;
  p.title = "Measured deviations against the power-law model";
  p.x_label = "\xCF\x84 (s)";
  p.y_label = "measured / model";
  std::vector<double> ys;
  const auto add = [&](const char* stat, const std::vector<double>& tau,
                       const std::vector<double>& model) {
    for (const auto& [name, s] : ch.stats) {
      if (name != stat) continue;
      svg::Series se;
      se.label = std::string(stat) + " / model";
      se.color = stat_color(stat);
      se.dots = true;
      for (std::size_t i = 0, k = 0; i < tau.size() && i < model.size(); ++i) {
        while (k < s.tau_s.size() && s.tau_s[k] < tau[i])
          ++k;
        if (k == s.tau_s.size() || s.tau_s[k] != tau[i] || !(model[i] > 0)) continue;
        se.x.push_back(tau[i]);
        se.y.push_back(s.dev[k] / model[i]);
        if (k < s.dev_lo.size() && k < s.dev_hi.size()) {
          se.y_lo.push_back(s.dev_lo[k] / model[i]);
          se.y_hi.push_back(s.dev_hi[k] / model[i]);
        }
      }
      if (se.y_lo.size() != se.y.size()) se.y_lo.clear(), se.y_hi.clear();
      ys.insert(ys.end(), se.y.begin(), se.y.end());
      p.series.push_back(std::move(se));
    }
  };
  add("oadev", pr.tau, pr.adev_model);
  add("mdev", pr.mdev_tau, pr.mdev_model);
  if (p.series.empty()) return "";
  std::tie(p.x_min, p.x_max) = decade_range(pr.tau);
  ys.push_back(1.0);
  std::tie(p.y_min, p.y_max) = decade_range(ys);
  return "<div class=\"panel\">\n" + svg::render(p) + "</div>\n";
}

std::string clock_summary_table(const std::string& channel, const std::vector<Member>& members) {
  std::ostringstream h;
  h << "<table class=\"summary\"><tr><th class=\"l\">unit</th><th class=\"l\">status</th>";
  for (const int alpha : pl::kAlphas)
    h << "<th>" << pl::noise_type_name(alpha) << "<br><span class=\"small\">h<sub>" << alpha
      << "</sub>, Hz<sup>" << -1 - alpha << "</sup></span></th>";
  h << "<th>PSD cross-check<br><span class=\"small\">max |log&#8321;&#8320; ratio|</span></th>"
       "</tr>\n";
  for (const Member& m : members) {
    h << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(*m.unit, channel)) << "\">"
      << escape(m.unit->rec.device_id) << "</a></td><td class=\"l words"
      << (m.ch->status.is_ok() ? "" : " bad") << "\">" << escape(io::to_string(m.ch->status));
    if (m.ch->powerlaw && m.ch->powerlaw->status != "ok")
      h << " <span class=\"bad\">(power law: " << escape(m.ch->powerlaw->status) << ")</span>";
    h << "</td>";
    for (const int alpha : pl::kAlphas) {
      const io::PowerLawLevelRecord* l = nullptr;
      if (m.ch->powerlaw)
        for (const auto& x : m.ch->powerlaw->levels)
          if (x.alpha == alpha) l = &x;
      h << "<td" << (l && l->detected ? "" : " class=\"nd\"") << ">"
        << (l ? level_cell(*l) : std::string("&ndash;")) << "</td>";
    }
    h << "<td>" << (m.ch->crosscheck ? number(m.ch->crosscheck->max_abs_log10_ratio, 2) : "&ndash;")
      << "</td></tr>\n";
  }
  h << "</table>\n<p class=\"small\">Each clock's own levels: clocks are compared side by side, "
       "never pooled into one distribution.</p>\n";
  return h.str();
}

}  // namespace allanlot::report
