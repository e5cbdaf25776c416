#include "src/report/parts.hpp"

#include "kernels/allan/stats.hpp"
#include "kernels/simulate/simulate.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <cmath>

namespace allanlot::report {

using svg::escape;
using svg::number;

std::string adev_plot(const std::string& id, const io::ChannelResult& ch) {
  svg::Plot p;
  p.id = id;
  p.title = "Allan-family deviations and the eq. (3) fit";
  p.x_label = "\xCF\x84 (s)";
  p.y_label = "\xCF\x83(\xCF\x84) (" + (ch.units.empty() ? std::string("u") : ch.units) + ")";
  std::vector<double> all_tau;
  const kernels::StatResult* oadev = nullptr;
  for (const auto& [name, s] : ch.stats) {
    // TDEV, TTOTDEV, MTIE and TIE rms are time (angle) errors, u*s, not deviations of the rate:
    // another axis. They are in the export tables.
    const auto stat = kernels::parse_stat(name);
    if (stat && kernels::is_time_error(*stat)) continue;
    if (name == "oadev") oadev = &s;
    all_tau.insert(all_tau.end(), s.tau_s.begin(), s.tau_s.end());
    svg::Series se;
    se.label = name;
    se.color = stat_color(name);
    se.x = s.tau_s;
    se.y = s.dev;
    if (s.dev_lo.size() == s.dev.size() && s.dev_hi.size() == s.dev.size()) {
      se.y_lo = s.dev_lo;
      se.y_hi = s.dev_hi;
      if (s.confidence > 0)
        p.title = "Allan-family deviations (error bars: " + number(100 * s.confidence, 3) +
                  " % CI) and the eq. (3) fit";
    }
    se.dots = true;
    se.dot_size = name == "oadev" ? 4.5 : 3.5;
    se.width = name == "oadev" ? 1.6 : 1.1;
    p.series.push_back(std::move(se));
  }
  const auto [x0, x1] = decade_range(all_tau);
  p.x_min = x0;
  p.x_max = x1;
  if (ch.fit && !ch.fit->terms.empty() && kernels::has_terms(ch.fit->status)) {
    const auto th = theta_of(*ch.fit);
    // The fitted curve on the oadev taus where it was fitted, then each detected term as its
    // straight-line asymptote over the whole axis, labelled with its slope where it dominates.
    svg::Series model;
    model.label = "eq. (3) fit";
    model.color = "#000";
    model.width = 2.0;
    if (!ch.fit->tau.empty() && ch.fit->tau.size() == ch.fit->adev_model.size()) {
      model.x = ch.fit->tau;
      model.y = ch.fit->adev_model;
    } else if (oadev) {
      for (const double t : oadev->tau_s) {
        model.x.push_back(t);
        model.y.push_back(std::sqrt(kernels::eq3_avar(th, t)));
      }
    }
    std::vector<svg::Series> asym;
    for (std::size_t j = 0; j < kTerms.size(); ++j) {
      const io::TermRecord* t = find_term(*ch.fit, kTerms[j].name);
      if (!t || !t->detected || !(th[j] > 0)) continue;
      svg::Series a;
      a.label = std::string(kTerms[j].name) + ": slope " + kTerms[j].slope;
      a.color = kTerms[j].color;
      a.dash = "7 4";
      a.width = 1.4;
      for (const double x : {x0, x1}) {
        a.x.push_back(x);
        a.y.push_back(std::sqrt(th[j] * kernels::eq3_regressors(x)[j]));
      }
      // The label goes where the asymptote touches the curve: the geometric middle of the
      // taus where the term dominates the model, else where it comes closest to dominating.
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
      if (std::isfinite(bx))
        p.annotations.push_back({bx, std::sqrt(th[j] * kernels::eq3_regressors(bx)[j]),
                                 std::string(kTerms[j].name) + " (" + kTerms[j].slope + ")",
                                 kTerms[j].color, "middle", 0, -10});
      asym.push_back(std::move(a));
    }
    p.series.push_back(std::move(model));
    for (auto& a : asym)
      p.series.push_back(std::move(a));
    // The asymptotes can run far below the data; keep the y range on the curves.
    std::vector<double> ys;
    for (const auto& s : p.series)
      if (s.dash.empty()) {
        for (std::size_t i = 0; i < s.y.size(); ++i) {
          ys.push_back(s.y[i]);
          if (!s.y_lo.empty()) ys.push_back(s.y_lo[i]);
          if (!s.y_hi.empty()) ys.push_back(s.y_hi[i]);
        }
      }
    const auto [y0, y1] = decade_range(ys);
    p.y_min = y0;
    p.y_max = y1;
  }
  return svg::render(p);
}

std::string psd_plot(const std::string& id, const io::ChannelResult& ch,
                     const io::FitRecord* psd_fit) {
  svg::Plot p;
  p.id = id;
  p.title = "Power spectral density (one-sided) and the model";
  p.x_label = "f (Hz)";
  const std::string u = ch.units.empty() ? std::string("u") : ch.units;
  p.y_label = "PSD ((" + u + ")\xC2\xB2/Hz)";
  const io::PsdRecord& psd = *ch.psd;
  svg::Series m;
  m.label = "measured (Welch)";
  m.color = "#1f77b4";
  m.x = psd.f;
  m.y = psd.psd;
  m.dots = true;
  m.dot_size = 3.5;
  m.width = 1.2;
  p.series.push_back(m);
  const auto [x0, x1] = decade_range(psd.f);
  p.x_min = x0;
  p.x_max = x1;
  std::vector<double> ys = psd.psd;
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
        s.y.push_back(kernels::model_psd_one_sided(spec, f0));
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

std::string crosscheck_plot(const std::string& id, const io::CrosscheckRecord& c) {
  svg::Plot p;
  p.id = id;
  p.title = "Eq. (2) cross-check: Allan variance from the PSD / from the time series";
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
  p.y_label = "\xCF\x83(\xCF\x84) (" + (units.empty() ? std::string("u") : units) + ")";
  if (!d.band_before_lo.empty() && !d.band_before_hi.empty())
    p.bands.push_back({d.tau, d.band_before_lo, d.band_before_hi, "#d62728", 0.10, false,
                       "Monte Carlo band, before"});
  if (!d.band_lo.empty() && !d.band_hi.empty())
    p.bands.push_back({d.tau, d.band_lo, d.band_hi, "#2ca02c", 0.20, false,
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
    s.y = y;
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
    m.y = d.measured;
    m.dots = true;
    m.line = false;
    m.dot_size = 5;
    // The gap's own statistics: ln(avar) has standard deviation sqrt(2 / edf), so the
    // deviation's 1-sigma band is exp(+-sqrt(2 / edf) / 2).
    if (d.edf.size() == d.tau.size()) {
      for (std::size_t i = 0; i < d.tau.size(); ++i) {
        const double s = d.edf[i] > 0 ? 0.5 * std::sqrt(2.0 / d.edf[i]) : kNaN;
        m.y_lo.push_back(d.measured[i] * std::exp(-s));
        m.y_hi.push_back(d.measured[i] * std::exp(s));
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
