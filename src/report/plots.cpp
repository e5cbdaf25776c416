#include "src/report/parts.hpp"

#include "kernels/allan/stats.hpp"
#include "kernels/simulate/simulate.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace allanlot::report {

using svg::escape;
using svg::number;

namespace {

// The statistics of one panel, the default one (OADEV, TDEV) first, in the order computed.
std::vector<const std::pair<std::string, kernels::StatResult>*>
panel_stats(const io::ChannelResult& ch, bool time_error) {
  std::vector<const std::pair<std::string, kernels::StatResult>*> out;
  for (const auto& named : ch.stats) {
    const auto stat = kernels::parse_stat(named.first);
    if (!stat || kernels::is_time_error(*stat) != time_error || named.second.tau_s.empty())
      continue;
    out.push_back(&named);
  }
  const std::string first = time_error ? "tdev" : "oadev";
  std::stable_partition(out.begin(), out.end(), [&](const auto* s) { return s->first == first; });
  return out;
}

svg::Series stat_series(const std::string& name, const kernels::StatResult& s, double factor,
                        bool optional) {
  svg::Series se;
  se.label = name;
  se.color = stat_color(name);
  se.css_class = "s-" + sanitize(name);
  se.optional = optional;
  se.x = s.tau_s;
  for (const double v : s.dev)
    se.y.push_back(v * factor);
  if (s.dev_lo.size() == s.dev.size() && s.dev_hi.size() == s.dev.size()) {
    for (std::size_t i = 0; i < s.dev.size(); ++i) {
      se.y_lo.push_back(s.dev_lo[i] * factor);
      se.y_hi.push_back(s.dev_hi[i] * factor);
    }
    if (s.confidence > 0) se.label += " (bars: " + number(100 * s.confidence, 3) + " % CI)";
  }
  se.dots = true;
  se.dot_size = optional ? 3.5 : 4.5;
  se.width = optional ? 1.1 : 1.6;
  return se;
}

// The eq. (3) fit on the taus where it was fitted, then each detected term as its
// straight-line asymptote over the whole axis, labelled with its slope where it touches the
// curve (the paper's Figure 1); everything times `factor` (channel to axis units).
void add_fit(svg::Plot& p, const io::FitRecord& fit, const kernels::StatResult* oadev,
             double factor) {
  const auto th = theta_of(fit);
  svg::Series model;
  // A poor fit's model (docs/fit-and-psd.md): the curve is that model's, not eq. (3)'s alone.
  model.label = fit.model.empty() ? "eq. (3) fit" : "model: " + fit.model;
  model.color = "#000";
  model.width = 2.0;
  model.css_class = "fit";
  if (!fit.tau.empty() && fit.tau.size() == fit.adev_model.size()) {
    model.x = fit.tau;
    for (const double v : fit.adev_model)
      model.y.push_back(v * factor);
  } else if (oadev) {
    for (const double t : oadev->tau_s) {
      model.x.push_back(t);
      model.y.push_back(std::sqrt(kernels::eq3_avar(th, t)) * factor);
    }
  }
  std::vector<svg::Series> asym;
  for (std::size_t j = 0; j < kTerms.size(); ++j) {
    const io::TermRecord* t = find_term(fit, kTerms[j].name);
    if (!t || !t->detected || !(th[j] > 0)) continue;
    const auto term_dev = [&](double x) {
      return std::sqrt(th[j] * kernels::eq3_regressors(x)[j]) * factor;
    };
    svg::Series a;
    a.label = std::string(kTerms[j].name) + ": slope " + kTerms[j].slope;
    a.color = kTerms[j].color;
    a.dash = "7 4";
    a.width = 1.4;
    a.css_class = "term";
    for (const double x : {p.x_min, p.x_max}) {
      a.x.push_back(x);
      a.y.push_back(term_dev(x));
    }
    // The label's point: the geometric middle of the taus where the term dominates the model,
    // else where it comes closest to dominating; svg places the text clear of the curves.
    double best = -1, bx = kNaN, dom_lo = kNaN, dom_hi = kNaN;
    for (const double x : model.x) {
      const double f = th[j] * kernels::eq3_regressors(x)[j] / kernels::eq3_avar(th, x);
      if (f > best) {
        best = f;
        bx = x;
      }
      if (f > 0.5) {
        if (std::isnan(dom_lo)) dom_lo = x;
        dom_hi = x;
      }
    }
    if (std::isfinite(dom_lo)) bx = std::sqrt(dom_lo * dom_hi);
    if (std::isfinite(bx)) {
      svg::Annotation label;
      label.x = bx;
      label.y = term_dev(bx);
      label.text = std::string(kTerms[j].name) + " (" + kTerms[j].slope + ")";
      label.color = kTerms[j].color;
      label.avoid = true;
      label.css_class = "slope";
      p.annotations.push_back(std::move(label));
    }
    asym.push_back(std::move(a));
  }
  p.series.push_back(std::move(model));
  for (auto& a : asym)
    p.series.push_back(std::move(a));
}

// The tick boxes that show the optional statistics of panel `id`: siblings before its <svg>,
// so that the page's CSS (toggle_css) reaches the series from them.
std::string toggles(const std::string& id, const std::vector<svg::Series>& optional) {
  if (optional.empty()) return "";
  std::string h = "<span class=\"small\">Also show:</span>\n";
  for (const svg::Series& s : optional) {
    const std::string name = s.css_class.substr(2);  // "s-<stat>"
    const std::string box = id + "-t-" + name;
    h += "<input type=\"checkbox\" id=\"" + box + "\" class=\"t-" + name + "\"><label for=\"" +
         box + "\"><span class=\"sw\" style=\"background:" + escape(s.color) + "\"></span>" +
         escape(name) + "</label>\n";
  }
  return h;
}

}  // namespace

std::string toggle_css() {
  std::string css = ".opt{display:none}\n";
  for (const kernels::Stat s : kernels::all_stats()) {
    const std::string n = sanitize(kernels::stat_name(s));
    css += ".t-" + n + ":checked~svg .s-" + n + "{display:inline}\n";
  }
  return css;
}

std::string deviation_panel(const std::string& id, const io::ChannelResult& ch, bool time_error,
                            const std::vector<const masks::Mask*>& masks) {
  const auto stats = panel_stats(ch, time_error);
  if (stats.empty()) return "";
  const AxisUnits u = time_error ? time_error_axis_units(ch.units) : rate_axis_units(ch.units);
  svg::Plot p;
  p.id = id;
  p.x_label = "\xCF\x84 (s)";
  const bool clock = is_clock(ch.units);
  if (time_error) {
    p.title = "Time deviation (TDEV)";
    p.y_label = "time error (" + u.text() + ")";
  } else {
    p.title = clock ? "Allan deviation of the fractional frequency" : "Allan deviation";
    p.y_label =
        std::string(clock ? "\xCF\x83y(\xCF\x84)" : "\xCF\x83(\xCF\x84)") + " (" + u.text() + ")";
  }
  std::vector<double> all_tau;
  for (const auto* s : stats)
    all_tau.insert(all_tau.end(), s->second.tau_s.begin(), s->second.tau_s.end());
  std::tie(p.x_min, p.x_max) = decade_range(all_tau);
  std::vector<svg::Series> optional;
  p.series.push_back(stat_series(stats[0]->first, stats[0]->second, u.factor, false));
  for (std::size_t i = 1; i < stats.size(); ++i)
    optional.push_back(stat_series(stats[i]->first, stats[i]->second, u.factor, true));
  const kernels::StatResult* oadev = stats[0]->first == "oadev" ? &stats[0]->second : nullptr;
  if (!time_error && ch.fit && !ch.fit->terms.empty() && kernels::has_terms(ch.fit->status)) {
    p.title += " and the eq. (3) fit";
    add_fit(p, *ch.fit, oadev, u.factor);
  }
  if (!time_error && ch.powerlaw && ch.powerlaw->status == "ok") {
    p.title += " and the power-law model";
    add_powerlaw(p, ch, u.factor);
  }
  // The optional statistics last, so that their legend entries, hidden with them, leave no
  // gap; the y range over every statistic (not the asymptotes, which run far below).
  std::vector<double> ys;
  for (auto& s : optional)
    p.series.push_back(s);

  for (const auto& s : p.series)
    if (s.dash.empty()) {
      ys.insert(ys.end(), s.y.begin(), s.y.end());
      ys.insert(ys.end(), s.y_lo.begin(), s.y_lo.end());
      ys.insert(ys.end(), s.y_hi.begin(), s.y_hi.end());
    }
  // The spec's ITU-T masks (clocks.cpp) last, and in the y range where they meet the taus, so
  // that the margin to the mask shows.
  if (time_error && !masks.empty()) {
    const std::size_t first_mask = p.series.size();
    add_mask_series(p, masks, u.factor);
    for (std::size_t k = first_mask; k < p.series.size(); ++k)
      for (std::size_t i = 0; i < p.series[k].x.size(); ++i)
        if (p.series[k].x[i] >= p.x_min && p.series[k].x[i] <= p.x_max)
          ys.push_back(p.series[k].y[i]);
  }
  std::tie(p.y_min, p.y_max) = decade_range(ys);
  return "<div class=\"panel\">\n" + toggles(id, optional) + svg::render(p) + "</div>\n";
}

std::string psd_plot(const std::string& id, const io::ChannelResult& ch,
                     const io::FitRecord* psd_fit) {
  svg::Plot p;
  p.id = id;
  p.title = "Power spectral density (one-sided) and the model";
  p.x_label = "f (Hz)";
  // In the square of the Allan plot's units, so that the white level reads as N's density.
  const AxisUnits u = rate_axis_units(ch.units);
  const double f2 = u.factor * u.factor;
  p.y_label = u.unit == "1"    ? std::string("PSD (1/Hz)")
              : u.unit.empty() ? std::string("PSD (units\xC2\xB2/Hz)")
                               : "PSD ((" + u.unit + ")\xC2\xB2/Hz)";
  const io::PsdRecord& psd = *ch.psd;
  svg::Series m;
  m.label = "measured (Welch)";
  m.color = "#1f77b4";
  m.x = psd.f;
  for (const double v : psd.psd)
    m.y.push_back(v * f2);
  m.dots = true;
  m.dot_size = 3.5;
  m.width = 1.2;
  p.series.push_back(m);
  const auto [x0, x1] = decade_range(psd.f);
  p.x_min = x0;
  p.x_max = x1;
  std::vector<double> ys = m.y;
  // The model's one-sided PSD (kernels::model_psd_one_sided: the forms under the paper's
  // eq. (3), doubled). The ramp R is deterministic and has no density.
  const auto model_curve = [&](const io::FitRecord& f, const char* label, const char* color,
                               const char* dash) {
    kernels::ChannelSpec spec;
    spec.rate_hz = ch.sample_rate_hz > 0 ? ch.sample_rate_hz : 1.0;
    for (const auto& t : f.terms) {
      const double v = std::isfinite(t.value) ? t.value : 0.0;
      if (t.term == "K") spec.terms.K = v;
      if (t.term == "B") spec.terms.B = v;
      if (t.term == "N") spec.terms.N = v;
      if (t.term == "Q") spec.terms.Q = v;
    }
    svg::Series s;
    s.label = label;
    s.color = color;
    s.dash = dash;
    s.width = 2.0;
    for (const double f0 : psd.f)
      if (f0 > 0) {
        s.x.push_back(f0);
        s.y.push_back(kernels::model_psd_one_sided(spec, f0) * f2);
      }
    return s;
  };
  if (ch.fit && kernels::has_terms(ch.fit->status) && !ch.fit->terms.empty()) {
    svg::Series s = model_curve(*ch.fit, "eq. (3) fit (Allan)", "#000", "");
    ys.insert(ys.end(), s.y.begin(), s.y.end());
    p.series.push_back(std::move(s));
    // The individual terms' densities: slopes -2 (K), -1 (B), 0 (N), +2 (Q).
    for (std::size_t j = 1; j < kTerms.size(); ++j) {
      const io::TermRecord* t = find_term(*ch.fit, kTerms[j].name);
      if (!t || !t->detected || !(t->value > 0)) continue;
      io::FitRecord one;
      one.terms.push_back(*t);
      svg::Series a = model_curve(one, "", kTerms[j].color, "7 4");
      a.width = 1.3;
      a.label = std::string(kTerms[j].name) + " term";
      p.series.push_back(std::move(a));
    }
  }
  if (psd_fit && !psd_fit->terms.empty())
    p.series.push_back(model_curve(*psd_fit, "eq. (3) fit (PSD)", "#d62728", "2 3"));
  const auto [y0, y1] = decade_range(ys);
  p.y_min = y0;
  p.y_max = y1;
  return svg::render(p);
}

std::string crosscheck_plot(const std::string& id, const io::CrosscheckRecord& c, bool clock) {
  svg::Plot p;
  p.id = id;
  // A clock's page names the comparison by what it is, not by the paper's equation.
  p.title = std::string(clock ? "PSD cross-check" : "Eq. (2) cross-check") +
            ": Allan variance from the PSD / from the time series";
  p.x_label = "\xCF\x84 (s)";
  p.y_label = "ratio avar_psd / avar_time";
  svg::Series valid, invalid;
  valid.label = "ratio (valid \xCF\x84)";
  valid.color = "#1f77b4";
  valid.dots = true;
  valid.line = true;
  invalid.label = "ratio (outside the valid range)";
  invalid.color = "#bbb";
  invalid.dots = true;
  invalid.line = false;
  double lo = 0.5, hi = 2.0;
  for (std::size_t i = 0; i < c.tau.size() && i < c.ratio.size(); ++i) {
    const bool ok = i < c.valid.size() && c.valid[i];
    (ok ? valid : invalid).x.push_back(c.tau[i]);
    (ok ? valid : invalid).y.push_back(c.ratio[i]);
    (ok ? invalid : valid).x.push_back(c.tau[i]);
    (ok ? invalid : valid).y.push_back(kNaN);  // breaks the other series' line here
    if (std::isfinite(c.ratio[i]) && c.ratio[i] > 0) {
      lo = std::min(lo, c.ratio[i]);
      hi = std::max(hi, c.ratio[i]);
    }
  }
  if (c.valid_tau_range.size() == 2 && c.valid_tau_range[0] > 0) {
    svg::Band b;
    b.vertical = true;
    b.x = c.valid_tau_range;
    b.color = "#2ca02c";
    b.opacity = 0.08;
    b.label = "valid \xCF\x84 range";
    p.bands.push_back(b);
  }
  p.hlines.push_back({1.0, "#444", "5 3"});
  p.series.push_back(std::move(valid));
  if (!invalid.x.empty()) p.series.push_back(std::move(invalid));
  const auto [x0, x1] = decade_range(c.tau);
  p.x_min = x0;
  p.x_max = x1;
  p.y_min = std::max(lo / 1.2, 1e-3);
  p.y_max = std::min(hi * 1.2, 1e3);
  return svg::render(p);
}

std::string diagnosis_plot(const std::string& id, const io::DiagnosisView& d,
                           const std::string& units) {
  svg::Plot p;
  p.id = id;
  p.title = "Diagnosis: measured and model, before and after";
  p.x_label = "\xCF\x84 (s)";
  // In the Allan plot's units, as the channel's other plots.
  const AxisUnits u = rate_axis_units(units);
  p.y_label = "\xCF\x83(\xCF\x84) (" + u.text() + ")";
  const auto scaled = [&](std::vector<double> v) {
    for (double& x : v)
      x *= u.factor;
    return v;
  };
  if (!d.band_before_lo.empty() && !d.band_before_hi.empty())
    p.bands.push_back({d.tau, scaled(d.band_before_lo), scaled(d.band_before_hi), "#d62728", 0.10,
                       false, "Monte Carlo band, before"});
  if (!d.band_lo.empty() && !d.band_hi.empty())
    p.bands.push_back({d.tau, scaled(d.band_lo), scaled(d.band_hi), "#2ca02c", 0.20, false,
                       d.band_before_lo.empty() ? "Monte Carlo band" : "Monte Carlo band, after"});
  const auto gap = [](double g) { return std::isnan(g) ? std::string() : ", gap " + number(g, 3); };
  // The model before (dashed red) and after (solid black), each labelled with its gap.
  const auto model = [&](const std::vector<double>& y, const char* label, double g,
                         const char* color, const char* dash) {
    svg::Series s;
    s.label = label + gap(g);
    s.color = color;
    s.dash = dash;
    s.width = 2.0;
    s.x = d.tau;
    s.y = scaled(y);
    return s;
  };
  if (!d.model_before.empty())
    p.series.push_back(model(d.model_before, "model before", d.gap_before, "#d62728", "7 4"));
  if (!d.model_after.empty())
    p.series.push_back(model(d.model_after, "model after", d.gap_after, "#000", ""));
  if (!d.measured.empty()) {
    svg::Series m;
    m.label = "measured";
    m.color = "#1f77b4";
    m.x = d.tau;
    m.y = scaled(d.measured);
    m.dots = true;
    m.line = false;
    m.dot_size = 5;
    // The gap's own statistics: ln(avar) has standard deviation sqrt(2 / edf), so the
    // deviation's 1-sigma band is exp(+-sqrt(2 / edf) / 2).
    if (d.edf.size() == d.tau.size()) {
      for (std::size_t i = 0; i < d.tau.size(); ++i) {
        const double s = d.edf[i] > 0 ? 0.5 * std::sqrt(2.0 / d.edf[i]) : kNaN;
        m.y_lo.push_back(m.y[i] * std::exp(-s));
        m.y_hi.push_back(m.y[i] * std::exp(s));
      }
    }
    p.series.push_back(std::move(m));
  }
  const auto [x0, x1] = decade_range(d.tau);
  p.x_min = x0;
  p.x_max = x1;
  return svg::render(p);
}

}  // namespace allanlot::report
