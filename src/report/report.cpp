#include "src/report/report.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/report_data.hpp"
#include "io/results.hpp"
#include "kernels/fit.hpp"
#include "kernels/simulate.hpp"
#include "kernels/units.hpp"
#include "src/lot/statistics.hpp"
#include "src/report/svg.hpp"

#include <allanlot/version.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

namespace allanlot::cli {
namespace {

namespace fs = std::filesystem;
using svg::escape;
using svg::number;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Names, ids and colours.

// An id or file name made of [A-Za-z0-9_-] only: device ids and channel paths come from the
// data, and must neither break the HTML nor lead a link outside the report's directory.
std::string sanitize(std::string_view s) {
  std::string out;
  for (const char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    out += ok ? c : '_';
  }
  if (out.empty()) out = "_";
  return out;
}

// Distinct, colour-blind-safe-ish colours per statistic (matplotlib's tab10 order), the same
// on every plot so that a reader learns them once.
std::string stat_color(const std::string& s) {
  static const std::map<std::string, std::string> c = {{"oadev", "#1f77b4"}, {"adev", "#17becf"},
                                                       {"mdev", "#2ca02c"},  {"hdev", "#9467bd"},
                                                       {"ohdev", "#d62728"}, {"totdev", "#8c564b"}};
  const auto it = c.find(s);
  return it == c.end() ? "#7f7f7f" : it->second;
}

// The eq. (3) terms with their Allan-deviation slope (the paper's Figure 1: mu of
// sigma(tau) ~ tau^mu) and a colour for their asymptote.
struct TermStyle {
  const char* name;
  const char* slope;  // as printed
  const char* color;
  const char* meaning;
};
constexpr std::array<TermStyle, 5> kTerms = {{
    {"R", "+1", "#e377c2", "rate ramp"},
    {"K", "+1/2", "#ff7f0e", "rate random walk"},
    {"B", "0", "#bcbd22", "bias instability (flicker)"},
    {"N",
     "\xE2\x88\x92"
     "1/2",
     "#17becf", "white rate noise (ARW/VRW)"},
    {"Q",
     "\xE2\x88\x92"
     "1",
     "#7f7f7f", "quantization"},
}};

int term_index(const std::string& name) {
  for (std::size_t i = 0; i < kTerms.size(); ++i)
    if (name == kTerms[i].name) return static_cast<int>(i);
  return -1;
}

// ---------------------------------------------------------------------------------------------
// Lot-summary columns added by other commands (spec_status, fits_agree), looked up by
// (device, channel). Absent columns leave every field empty: no colouring.

struct RowExtras {
  std::string spec;  // whole-row spec status: pass, fail, undecided, or ""
  std::array<std::string, 5> term_spec;
  std::string agree;  // "yes", "no" or ""
  std::array<std::string, 5> term_agree;
};

std::string lower(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string spec_class(const std::string& v) {
  const std::string l = lower(v);
  if (l == "pass" || l == "passed" || l == "ok") return "pass";
  if (l == "fail" || l == "failed") return "fail";
  if (l == "undecided" || l == "unknown" || l == "marginal") return "undecided";
  return "";
}

std::string agree_value(const std::string& v) {
  const std::string l = lower(v);
  if (l == "1" || l == "true" || l == "yes" || l == "agree") return "yes";
  if (l == "0" || l == "false" || l == "no" || l == "disagree") return "no";
  return "";
}

using ExtrasMap = std::map<std::pair<std::string, std::string>, RowExtras>;

struct FailedInput {
  std::string device_id, source_file, status;
};

void read_lot_extras(const io::SummaryColumns& c, ExtrasMap& map,
                     std::vector<FailedInput>& failed) {
  const int dev = c.find("device_id"), chan = c.find("channel"), status = c.find("status");
  if (dev < 0 || chan < 0) return;
  const int source = c.find("source_file");
  const auto col = [&](const std::string& a) { return c.find(a); };
  const int spec = col("spec_status"), agree = col("fits_agree");
  std::array<int, 5> tspec{}, tagree{};
  for (std::size_t t = 0; t < 5; ++t) {
    const std::string n = kTerms[t].name;
    tspec[t] = std::max(col(n + "_spec_status"), col("spec_status_" + n));
    tagree[t] = std::max(col(n + "_fits_agree"), col("fits_agree_" + n));
  }
  for (std::size_t r = 0; r < c.rows; ++r) {
    const std::string& d = c.values[static_cast<std::size_t>(dev)][r];
    const std::string& ch = c.values[static_cast<std::size_t>(chan)][r];
    if (ch.empty()) {
      if (status >= 0)
        failed.push_back({d, source >= 0 ? c.values[static_cast<std::size_t>(source)][r] : "",
                          c.values[static_cast<std::size_t>(status)][r]});
      continue;
    }
    RowExtras x;
    if (spec >= 0) x.spec = spec_class(c.values[static_cast<std::size_t>(spec)][r]);
    if (agree >= 0) x.agree = agree_value(c.values[static_cast<std::size_t>(agree)][r]);
    for (std::size_t t = 0; t < 5; ++t) {
      if (tspec[t] >= 0)
        x.term_spec[t] = spec_class(c.values[static_cast<std::size_t>(tspec[t])][r]);
      if (tagree[t] >= 0)
        x.term_agree[t] = agree_value(c.values[static_cast<std::size_t>(tagree[t])][r]);
    }
    map[{d, ch}] = x;
  }
}

// ---------------------------------------------------------------------------------------------
// The units of the lot.

struct Unit {
  fs::path file;
  io::RecordingResult rec;
  std::map<std::string, io::FitRecord> psd_fits;       // by channel path
  std::map<std::string, io::DiagnosisView> diagnoses;  // by channel path
  std::vector<std::string> notes;                      // what the extras could not read
  std::string anchor;                                  // id of its section
  std::string page;  // its own page, relative to the lot page ("" = in the lot page)
};

std::string channel_anchor(const Unit& u, const std::string& channel) {
  return u.anchor + "-" + sanitize(channel);
}

// Links from the lot page.
std::string unit_href(const Unit& u) {
  return u.page + "#" + u.anchor;
}

std::string channel_href(const Unit& u, const std::string& channel) {
  return u.page + "#" + channel_anchor(u, channel);
}

// ---------------------------------------------------------------------------------------------
// Numbers in tables.

std::string value_pm(double v, double s) {
  if (std::isnan(v)) return "&ndash;";
  std::string t = number(v, 3);
  if (std::isfinite(s) && s > 0) t += " &plusmn; " + number(s, 2);
  return t;
}

const io::TermRecord* find_term(const io::FitRecord& f, const std::string& name) {
  for (const auto& t : f.terms)
    if (t.term == name) return &t;
  return nullptr;
}

std::array<double, kernels::kNumTerms> theta_of(const io::FitRecord& f) {
  std::array<double, kernels::kNumTerms> th{};
  for (const auto& t : f.terms) {
    const int i = term_index(t.term);
    if (i >= 0 && std::isfinite(t.value)) th[static_cast<std::size_t>(i)] = t.value * t.value;
  }
  return th;
}

// ---------------------------------------------------------------------------------------------
// Plots of one channel.

// Decade-snapped x range of a set of taus, shared by the asymptotes so that they span the
// whole plot.
std::pair<double, double> decade_range(const std::vector<double>& v) {
  double lo = INFINITY, hi = 0;
  for (const double x : v)
    if (std::isfinite(x) && x > 0) {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  if (!(hi > 0)) return {1, 10};
  double a = std::floor(std::log10(lo) + 1e-9), b = std::ceil(std::log10(hi) - 1e-9);
  if (b <= a) b = a + 1;
  return {std::pow(10.0, a), std::pow(10.0, b)};
}

std::string adev_plot(const std::string& id, const io::ChannelResult& ch) {
  svg::Plot p;
  p.id = id;
  p.title = "Allan-family deviations and the eq. (3) fit";
  p.x_label = "\xCF\x84 (s)";
  p.y_label = "\xCF\x83(\xCF\x84) (" + (ch.units.empty() ? std::string("u") : ch.units) + ")";
  std::vector<double> all_tau;
  const kernels::StatResult* oadev = nullptr;
  for (const auto& [name, s] : ch.stats) {
    // TDEV is a time (angle) error, u*s, not a deviation of the rate: another axis. It is in
    // the export tables.
    if (name == "tdev") continue;
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
  if (ch.fit && !ch.fit->terms.empty() && ch.fit->status == "ok") {
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
  if (ch.fit && ch.fit->status == "ok" && !ch.fit->terms.empty()) {
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
  if (!d.model_before.empty()) {
    svg::Series b;
    b.label = "model before" + gap(d.gap_before);
    b.color = "#d62728";
    b.dash = "7 4";
    b.width = 2.0;
    b.x = d.tau;
    b.y = d.model_before;
    p.series.push_back(std::move(b));
  }
  if (!d.model_after.empty()) {
    svg::Series a;
    a.label = "model after" + gap(d.gap_after);
    a.color = "#000";
    a.width = 2.0;
    a.x = d.tau;
    a.y = d.model_after;
    p.series.push_back(std::move(a));
  }
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

// ---------------------------------------------------------------------------------------------
// HTML.

const char* kCss =
    R"(body{font:14px/1.45 Helvetica,Arial,sans-serif;color:#222;margin:0 auto;max-width:1600px;padding:0 18px 40px}
h1{font-size:24px;margin:18px 0 6px}h2{font-size:19px;border-bottom:2px solid #ccc;padding-bottom:3px;margin-top:28px}
h3{font-size:16px;margin:22px 0 6px}h4{font-size:14px;margin:12px 0 4px}
table{border-collapse:collapse;margin:6px 0 14px;font-size:13px}
th,td{border:1px solid #ccc;padding:2px 7px;text-align:right;vertical-align:top;white-space:nowrap}
th{background:#f1f1f1}td.l,th.l{text-align:left}td.wrap{white-space:normal;max-width:900px;word-break:break-word;font-size:12px}
.pass{background:#cdeccf}.fail{background:#f6c4c4}.undecided{background:#fbeab5}
.nd{color:#999}.bad{color:#b00;font-weight:bold}.small{font-size:12px;color:#555}
.plots{display:grid;grid-template-columns:repeat(auto-fill,minmax(520px,1fr));gap:10px;margin:6px 0}
.plots>div{overflow-x:auto}
svg.plot{width:100%;height:auto;display:block;border:1px solid #e4e4e4}
.dists{display:grid;grid-template-columns:repeat(auto-fill,minmax(420px,1fr));gap:10px}
.tables{display:flex;flex-wrap:wrap;gap:0 28px}
nav.units a{display:inline-block;margin:0 10px 2px 0}
.legend-key span{display:inline-block;padding:0 8px;margin-right:6px;border:1px solid #ccc}
@media print{.plots{grid-template-columns:1fr 1fr}section.unit{break-before:page}}
)";

std::string html_head(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta "
         "name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         escape(title) + "</title>\n<style>\n" + kCss + "</style>\n</head>\n<body>\n";
}

std::string coefficient_table(const io::ChannelResult& ch, const io::FitRecord* psd_fit,
                              const RowExtras* x) {
  std::ostringstream h;
  const io::FitRecord& f = *ch.fit;
  h << "<table class=\"coef\"><tr><th class=\"l\">term</th><th>slope &mu;</th><th>value &plusmn; "
       "1&sigma;</th><th class=\"l\">unit</th><th>detected<br><span class=\"small\">else 95 % "
       "upper bound</span></th>";
  if (psd_fit) h << "<th>PSD fit &plusmn; 1&sigma;</th>";
  h << "</tr>\n";
  for (std::size_t j = 0; j < kTerms.size(); ++j) {
    const io::TermRecord* t = find_term(f, kTerms[j].name);
    if (!t) continue;
    std::string cls = x ? spec_class(x->term_spec[j]) : "";
    h << "<tr" << (cls.empty() ? "" : " class=\"" + cls + "\"") << "><td class=\"l\" title=\""
      << kTerms[j].meaning << "\"><b>" << kTerms[j].name << "</b></td><td>" << kTerms[j].slope
      << "</td><td" << (t->detected ? "" : " class=\"nd\"") << ">"
      << value_pm(t->value_datasheet, t->sigma_datasheet) << "</td><td class=\"l\">"
      << escape(t->unit_datasheet);
    // The other common datasheet form (ARW in deg/sqrt(h), Q in deg) under the primary one.
    if (!t->unit_datasheet_alt.empty() && t->detected)
      h << "<br><span class=\"small\">= " << number(t->value_datasheet_alt, 3) << " "
        << escape(t->unit_datasheet_alt) << "</span>";
    h << "</td><td>";
    if (t->detected)
      h << "yes";
    else
      h << "<span class=\"nd\">no, &lt; "
        << (std::isfinite(t->upper_datasheet) ? number(t->upper_datasheet, 2) : "?") << "</span>";
    h << "</td>";
    if (psd_fit) {
      const io::TermRecord* q = find_term(*psd_fit, kTerms[j].name);
      const std::string agree = x ? x->term_agree[j] : "";
      h << "<td" << (agree == "no" ? " class=\"bad\" title=\"the two fits disagree\"" : "") << ">"
        << (q ? value_pm(q->value_datasheet, q->sigma_datasheet) : std::string("&ndash;"))
        << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string diagnosis_section(const std::string& id, const io::DiagnosisView& d,
                              const std::string& units) {
  std::ostringstream h;
  h << "<h4>Diagnosis</h4>\n<p>Effects named, in the order they were added: ";
  if (d.effects_named.empty()) {
    h << "<i>none (the model already agrees)</i>";
  } else {
    for (std::size_t i = 0; i < d.effects_named.size(); ++i)
      h << (i ? " &rarr; " : "") << "<b>" << escape(d.effects_named[i]) << "</b>";
  }
  h << ". Gap before: " << number(d.gap_before, 3) << ", after: " << number(d.gap_after, 3)
    << " (about 1 = agreement within statistical noise).</p>\n";
  // The plot and, beside it, the iterations and the group's attributes.
  h << "<div class=\"plots\">";
  if (!d.tau.empty() && (!d.measured.empty() || !d.model_after.empty()))
    h << diagnosis_plot(id, d, units);
  h << "<div>\n";
  // One row per iteration (effect added): whatever per-iteration datasets there are.
  const std::size_t iterations =
      std::max({d.effects_named.size(), d.iteration_gap_before.size(), d.iteration_gap_after.size(),
                d.iteration_delta_ic.size(), d.iteration_parameters.size()});
  if (iterations > 0) {
    h << "<table><tr><th>iteration</th><th class=\"l\">effect added</th><th>gap before</th>"
         "<th>gap after</th><th>&Delta;IC</th><th class=\"l\">parameters</th></tr>\n";
    const auto num = [](const std::vector<double>& v, std::size_t i) {
      return i < v.size() ? number(v[i], 3) : std::string("&ndash;");
    };
    for (std::size_t i = 0; i < iterations; ++i)
      h << "<tr><td>" << i + 1 << "</td><td class=\"l\">"
        << (i < d.effects_named.size() ? escape(d.effects_named[i]) : std::string()) << "</td><td>"
        << num(d.iteration_gap_before, i) << "</td><td>" << num(d.iteration_gap_after, i)
        << "</td><td>" << num(d.iteration_delta_ic, i) << "</td><td class=\"l wrap\">"
        << (i < d.iteration_parameters.size() ? escape(d.iteration_parameters[i]) : std::string())
        << "</td></tr>\n";
    h << "</table>\n";
  }
  // Everything else diagnose recorded (models, settings) folded away: it can be long.
  if (!d.attributes.empty()) {
    h << "<details><summary class=\"small\">All attributes of the diagnosis group</summary>"
         "<table><tr><th class=\"l\">attribute</th><th class=\"l\">value</th></tr>\n";
    for (const auto& [k, v] : d.attributes)
      h << "<tr><td class=\"l\">" << escape(k) << "</td><td class=\"l wrap\">"
        << escape(v.size() > 2000 ? v.substr(0, 2000) + "..." : v) << "</td></tr>\n";
    h << "</table></details>\n";
  }
  h << "</div></div>\n";
  for (const std::string& n : d.notes)
    h << "<p class=\"small\">" << escape(n) << "</p>\n";
  return h.str();
}

std::string channel_section(const Unit& u, const io::ChannelResult& ch, const ExtrasMap& extras) {
  std::ostringstream h;
  const std::string id = channel_anchor(u, ch.path);
  const auto xit = extras.find({u.rec.device_id, ch.path});
  const RowExtras* x = xit == extras.end() ? nullptr : &xit->second;
  const auto pf = u.psd_fits.find(ch.path);
  const io::FitRecord* psd_fit = pf == u.psd_fits.end() ? nullptr : &pf->second;
  h << "<section class=\"channel\" id=\"" << id << "\">\n<h3>" << escape(u.rec.device_id)
    << " &middot; " << escape(ch.path) << "</h3>\n<p class=\"small\">units " << escape(ch.units)
    << ", " << number(ch.sample_rate_hz, 6) << " Hz, " << ch.n_samples << " samples ("
    << number(ch.n_samples / std::max(ch.sample_rate_hz, 1e-300), 4) << " s), " << ch.n_gaps
    << " gaps, " << escape(ch.data_type) << " data";
  if (ch.fit)
    h << "; fit " << escape(ch.fit->status) << ", &chi;&sup2;/dof " << number(ch.fit->chi2_dof, 3);
  if (ch.crosscheck)
    h << "; eq. (2) max |log&#8321;&#8320; ratio| "
      << number(ch.crosscheck->max_abs_log10_ratio, 3);
  if (x && !x->spec.empty())
    h << "; spec: <span class=\"" << x->spec << "\">" << x->spec << "</span>";
  if (x && x->agree == "no") h << "; <span class=\"bad\">time- and PSD-domain fits disagree</span>";
  h << "</p>\n";
  if (ch.status != "ok") h << "<p class=\"bad\">" << escape(ch.status) << "</p>\n";
  if (!ch.notes.empty()) h << "<p class=\"small\">Notes: " << escape(ch.notes) << "</p>\n";
  if (ch.status == "ok") {
    h << "<div class=\"plots\">\n";
    if (!ch.stats.empty()) h << adev_plot(id + "-adev", ch);
    if (ch.psd && !ch.psd->f.empty()) h << psd_plot(id + "-psd", ch, psd_fit);
    if (ch.crosscheck && !ch.crosscheck->tau.empty())
      h << crosscheck_plot(id + "-xc", *ch.crosscheck);
    // The coefficient table fills the grid's fourth cell, beside the cross-check.
    if (ch.fit && !ch.fit->terms.empty())
      h << "<div><h4>Equation (3) coefficients (datasheet units)</h4>\n"
        << coefficient_table(ch, psd_fit, x) << "</div>\n";
    h << "</div>\n";
  }
  const auto d = u.diagnoses.find(ch.path);
  if (d != u.diagnoses.end()) h << diagnosis_section(id + "-diag", d->second, ch.units);
  h << "</section>\n";
  return h.str();
}

std::string unit_section(const Unit& u, const ExtrasMap& extras, const std::string& lot_href) {
  std::ostringstream h;
  h << "<section class=\"unit\" id=\"" << u.anchor << "\">\n<h2>Unit " << escape(u.rec.device_id)
    << "</h2>\n<p class=\"small\">results " << escape(u.file.filename().string()) << "; source "
    << escape(u.rec.source_file) << "; " << escape(u.rec.tool_version) << "; created "
    << escape(u.rec.created_utc) << " &middot; <a href=\"" << escape(lot_href)
    << "\">back to the lot</a></p>\n";
  h << "<p class=\"small\">Channels: ";
  for (std::size_t i = 0; i < u.rec.channels.size(); ++i)
    h << (i ? ", " : "") << "<a href=\"#" << channel_anchor(u, u.rec.channels[i].path) << "\">"
      << escape(u.rec.channels[i].path) << "</a>";
  h << "</p>\n";
  for (const std::string& n : u.notes)
    h << "<p class=\"small\">" << escape(n) << "</p>\n";
  for (const auto& ch : u.rec.channels)
    h << channel_section(u, ch, extras);
  h << "</section>\n";
  return h.str();
}

// ---------------------------------------------------------------------------------------------
// The lot page: per-channel summary tables, distributions across units, outliers.

struct Member {
  const Unit* unit;
  const io::ChannelResult* ch;
};

struct Outlier {
  const Unit* unit;
  std::string channel;
  std::size_t term;
  double value, ratio, z;
  std::string unit_ds;
};

// The units the lot rule (src/lot/statistics.hpp, the lot summary's) flags on a term,
// through the summary rows of their results, so that the report lists exactly the outliers of
// lot_summary.csv, with the same z.
std::vector<Outlier> lot_outliers(const std::vector<Unit>& units) {
  std::vector<io::SummaryRow> rows;
  std::vector<const Unit*> owner;
  for (const Unit& u : units)
    for (io::SummaryRow& r : io::summary_rows(u.rec)) {
      rows.push_back(std::move(r));
      owner.push_back(&u);
    }
  std::vector<Outlier> out;
  for (const lot::TermOutlier& o : lot::compute_lot_statistics(rows).outliers) {
    const io::SummaryRow& r = rows[o.row];
    out.push_back({owner[o.row], r.channel, o.term, r.value[o.term], r.value[o.term] / o.median,
                   o.z, r.unit[o.term]});
  }
  return out;
}

std::string distribution_plot(const std::string& id, const std::string& channel,
                              const std::vector<Member>& members,
                              const std::vector<Outlier>& outliers) {
  svg::Plot p;
  p.id = id;
  p.title = "Spread across units: " + channel;
  p.x_scale = svg::Scale::Categorical;
  p.y_label = "value / lot median";
  p.height = 300;
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
    p.categories.push_back(label + "\n" + number(median_value, 3));
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

std::string summary_table(const std::string& channel, const std::vector<Member>& members,
                          const ExtrasMap& extras) {
  std::ostringstream h;
  // Units per term from the first unit that has them (a channel has the same units across a
  // lot; a unit whose units differ shows them in its cell).
  std::array<std::string, 5> header_unit;
  for (const Member& m : members)
    if (m.ch->fit)
      for (std::size_t j = 0; j < 5; ++j)
        if (const auto* t = find_term(*m.ch->fit, kTerms[j].name); t && header_unit[j].empty())
          header_unit[j] = t->unit_datasheet;
  bool any_spec = false, any_agree = false;
  for (const Member& m : members) {
    const auto it = extras.find({m.unit->rec.device_id, channel});
    if (it == extras.end()) continue;
    any_spec = any_spec || !it->second.spec.empty();
    any_agree = any_agree || !it->second.agree.empty();
  }
  h << "<table class=\"summary\"><tr><th class=\"l\">unit</th><th class=\"l\">status</th>";
  for (std::size_t j = 0; j < 5; ++j)
    h << "<th>" << kTerms[j].name << "<br><span class=\"small\">" << escape(header_unit[j])
      << "</span></th>";
  h << "<th>&chi;&sup2;/dof</th><th>eq. (2)<br><span class=\"small\">max |log&#8321;&#8320; "
       "ratio|</span></th>";
  if (any_spec) h << "<th>spec</th>";
  if (any_agree) h << "<th>fits agree</th>";
  h << "</tr>\n";
  for (const Member& m : members) {
    const auto it = extras.find({m.unit->rec.device_id, channel});
    const RowExtras* x = it == extras.end() ? nullptr : &it->second;
    h << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(*m.unit, channel)) << "\">"
      << escape(m.unit->rec.device_id) << "</a></td>";
    h << "<td class=\"l" << (m.ch->status == "ok" ? "" : " bad") << "\">" << escape(m.ch->status);
    if (m.ch->fit && m.ch->fit->status != "ok")
      h << " <span class=\"bad\">(fit: " << escape(m.ch->fit->status) << ")</span>";
    h << "</td>";
    for (std::size_t j = 0; j < 5; ++j) {
      const io::TermRecord* t = m.ch->fit ? find_term(*m.ch->fit, kTerms[j].name) : nullptr;
      std::string cls = x ? spec_class(x->term_spec[j]) : "";
      if (!t || !t->detected) cls += cls.empty() ? "nd" : " nd";
      if (x && x->term_agree[j] == "no") cls += cls.empty() ? "bad" : " bad";
      h << "<td" << (cls.empty() ? "" : " class=\"" + cls + "\"") << ">";
      if (t) {
        h << (t->detected ? value_pm(t->value_datasheet, t->sigma_datasheet)
                          : "&lt; " + number(t->upper_datasheet, 2));
        if (t->unit_datasheet != header_unit[j])
          h << " <span class=\"small\">" << escape(t->unit_datasheet) << "</span>";
      } else {
        h << "&ndash;";
      }
      h << "</td>";
    }
    h << "<td>" << (m.ch->fit ? number(m.ch->fit->chi2_dof, 3) : "&ndash;") << "</td><td>"
      << (m.ch->crosscheck ? number(m.ch->crosscheck->max_abs_log10_ratio, 2) : "&ndash;")
      << "</td>";
    if (any_spec)
      h << "<td" << (x && !x->spec.empty() ? " class=\"" + x->spec + "\">" + x->spec : ">")
        << "</td>";
    if (any_agree)
      h << "<td" << (x && x->agree == "no" ? " class=\"bad\"" : "") << ">" << (x ? x->agree : "")
        << "</td>";
    h << "</tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string lot_section(const std::string& title, const std::vector<Unit>& units,
                        const ExtrasMap& extras, const std::vector<FailedInput>& failed_inputs,
                        const std::vector<std::string>& problems) {
  std::ostringstream h;
  // Channels in the order of their first appearance across the (sorted) units.
  std::vector<std::string> channels;
  std::map<std::string, std::vector<Member>> by_channel;
  std::size_t n_channels = 0, n_failed = 0;
  std::set<std::string> versions;
  std::string first_created, last_created;
  for (const Unit& u : units) {
    versions.insert(u.rec.tool_version);
    if (first_created.empty() || u.rec.created_utc < first_created)
      first_created = u.rec.created_utc;
    last_created = std::max(last_created, u.rec.created_utc);
    for (const auto& ch : u.rec.channels) {
      if (!by_channel.count(ch.path)) channels.push_back(ch.path);
      by_channel[ch.path].push_back({&u, &ch});
      ++n_channels;
      n_failed += ch.status == "ok" ? 0 : 1;
    }
  }
  std::array<std::size_t, 3> spec_count{};
  for (const auto& [key, x] : extras) {
    if (x.spec == "pass") ++spec_count[0];
    if (x.spec == "fail") ++spec_count[1];
    if (x.spec == "undecided") ++spec_count[2];
  }
  h << "<section id=\"lot\">\n<h1>" << escape(title) << "</h1>\n<p>" << units.size() << " units, "
    << n_channels << " channels (" << n_failed << " failed)";
  if (!failed_inputs.empty()) h << ", " << failed_inputs.size() << " inputs that failed";
  h << ". Results written " << escape(first_created)
    << (last_created != first_created ? " to " + escape(last_created) : std::string()) << " by ";
  bool first = true;
  for (const auto& v : versions) {
    h << (first ? "" : ", ") << "allanlot " << escape(v);
    first = false;
  }
  h << "; report by allanlot " << escape(kVersion) << ".";
  if (spec_count[0] + spec_count[1] + spec_count[2] > 0)
    h << " Spec: <span class=\"pass\">" << spec_count[0] << " pass</span> <span class=\"fail\">"
      << spec_count[1] << " fail</span> <span class=\"undecided\">" << spec_count[2]
      << " undecided</span>.";
  h << "</p>\n";
  if (!problems.empty() || !failed_inputs.empty()) {
    h << "<h2>Problems</h2>\n<ul>\n";
    for (const auto& p : problems)
      h << "<li class=\"bad\">" << escape(p) << "</li>\n";
    for (const auto& f : failed_inputs)
      h << "<li class=\"bad\">" << escape(f.device_id) << " (" << escape(f.source_file)
        << "): " << escape(f.status) << "</li>\n";
    h << "</ul>\n";
  }
  h << "<nav class=\"units\"><b>Units:</b> ";
  for (const Unit& u : units) {
    std::size_t bad = 0;
    for (const auto& ch : u.rec.channels)
      bad += ch.status == "ok" ? 0 : 1;
    h << "<a href=\"" << escape(unit_href(u)) << "\"" << (bad ? " class=\"bad\"" : "") << ">"
      << escape(u.rec.device_id) << "</a>";
  }
  h << "</nav>\n";
  h << "<p class=\"small\">Values in datasheet units, &plusmn; 1&sigma;; grey: not detected "
       "(the 95 % upper bound is shown). Outliers, as in the lot summary: |value &minus; lot "
       "median| / &radic;(spread&sup2; + &sigma;&sup2;) above "
    << number(lot::kOutlierZ, 2) << ", spread = " << number(lot::kMadToSigma, 5)
    << " MAD, &sigma; the unit's own (at least " << lot::kMinUnitsForOutliers
    << " units, at least half of them detecting the term).</p>\n";
  const std::vector<Outlier> outliers = lot_outliers(units);
  std::ostringstream dists, tables;
  for (const std::string& c : channels) {
    const auto& members = by_channel[c];
    dists << distribution_plot("dist-" + sanitize(c), c, members, outliers);
    tables << "<div><h3 id=\"lot-" << sanitize(c) << "\">" << escape(c) << "</h3>\n"
           << summary_table(c, members, extras) << "</div>\n";
  }
  h << "<h2>Distributions across units</h2>\n<p class=\"small\">Each detected term of each "
       "unit relative to the lot median (labelled under its term), with the quartile box and "
       "1.5 IQR whiskers; outliers in red link to the unit.</p>\n<div class=\"dists\">\n"
    << dists.str() << "</div>\n";
  h << "<h2>Outlier units</h2>\n";
  if (outliers.empty()) {
    h << "<p>None.</p>\n";
  } else {
    h << "<table><tr><th class=\"l\">unit</th><th class=\"l\">channel</th><th>term</th>"
         "<th>value</th><th class=\"l\">unit</th><th>/ lot median</th><th>modified z</th></tr>\n";
    for (const Outlier& o : outliers)
      h << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(*o.unit, o.channel)) << "\">"
        << escape(o.unit->rec.device_id) << "</a></td><td class=\"l\">" << escape(o.channel)
        << "</td><td>" << kTerms[o.term].name << "</td><td>" << number(o.value, 3)
        << "</td><td class=\"l\">" << escape(o.unit_ds) << "</td><td>" << number(o.ratio, 3)
        << "</td><td>" << number(o.z, 3) << "</td></tr>\n";
    h << "</table>\n";
  }
  h << "<h2>Summary by channel</h2>\n<div class=\"tables\">\n"
    << tables.str() << "</div>\n</section>\n";
  return h.str();
}

// ---------------------------------------------------------------------------------------------

bool is_results_file(const fs::path& p) {
  const std::string n = p.filename().string();
  return n.size() > 9 && n.compare(n.size() - 9, 9, ".allan.h5") == 0 && n[0] != '.';
}

// The unit a diagnose output belongs to: by the file's root device_id; else by the input
// recording diagnose names in its `source_file` attribute (the results record theirs too);
// else by the file name, "<device>.h5" or "<device>.<anything>.h5".
Unit* match_unit(std::vector<Unit>& units, const io::ReportExtras& x, const io::DiagnosisView& d,
                 const fs::path& file) {
  if (!x.device_id.empty()) {
    for (Unit& u : units)
      if (u.rec.device_id == x.device_id) return &u;
    return nullptr;
  }
  for (const auto& [k, v] : d.attributes) {
    if (k != "source_file" || v.empty()) continue;
    std::error_code ec;
    const fs::path src = fs::weakly_canonical(fs::path(v), ec);
    for (Unit& u : units) {
      std::error_code ec2;
      if (!ec && src == fs::weakly_canonical(fs::path(u.rec.source_file), ec2) && !ec2) return &u;
    }
    for (Unit& u : units)
      if (fs::path(v).filename() == fs::path(u.rec.source_file).filename()) return &u;
  }
  const std::string name = file.filename().string();
  for (Unit& u : units)
    if (name.rfind(u.rec.device_id + ".", 0) == 0) return &u;
  return nullptr;
}

void attach_diagnoses(std::vector<Unit>& units, const io::ReportExtras& x, const fs::path& file,
                      std::ostream& err, bool quiet, std::vector<std::string>& problems) {
  for (const auto& d : x.diagnoses) {
    Unit* u = match_unit(units, x, d, file);
    if (!u) {
      const std::string msg = file.string() + ":" + d.channel +
                              "/diagnosis: no unit of the lot matches (by device_id, "
                              "source_file or file name); not shown";
      problems.push_back(msg);
      if (!quiet) err << "allanlot: warning: " << msg << "\n";
      continue;
    }
    u->diagnoses[d.channel] = d;
    for (const auto& n : x.notes)
      u->notes.push_back(file.filename().string() + ": " + n);
  }
}

}  // namespace

int run_report(const ReportOptions& opt, std::ostream& out, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_directory(opt.outdir, ec)) {
    err << "allanlot: usage error: " << opt.outdir.string() << ": not a directory\n";
    return kExitUsage;
  }
  std::vector<fs::path> files, others;
  for (const auto& e : fs::directory_iterator(opt.outdir, ec)) {
    if (!e.is_regular_file()) continue;
    if (is_results_file(e.path()))
      files.push_back(e.path());
    else if (e.path().extension() == ".h5" && e.path().filename() != "lot_summary.h5" &&
             e.path().filename().string()[0] != '.')
      others.push_back(e.path());
  }
  if (ec) {
    err << "allanlot: usage error: " << opt.outdir.string() << ": " << ec.message() << "\n";
    return kExitUsage;
  }
  std::sort(files.begin(), files.end());
  std::sort(others.begin(), others.end());
  if (files.empty()) {
    err << "allanlot: usage error: " << opt.outdir.string()
        << ": no results files (*.allan.h5); run 'allanlot analyze -o " << opt.outdir.string()
        << " ...' first\n";
    return kExitUsage;
  }

  std::vector<Unit> units;
  std::vector<std::string> problems;
  for (const fs::path& f : files) {
    Unit u;
    u.file = f;
    try {
      u.rec = io::read_results(f);
    } catch (const std::exception& e) {
      problems.push_back(std::string(e.what()));
      err << "allanlot: error: " << e.what() << "\n";
      continue;
    }
    try {
      io::ReportExtras x = io::read_report_extras(f);
      for (auto& [chan, fit] : x.psd_fits)
        u.psd_fits[chan] = std::move(fit);
      for (auto& d : x.diagnoses)
        u.diagnoses[d.channel] = std::move(d);
      u.notes = std::move(x.notes);
    } catch (const std::exception& e) {
      u.notes.push_back(e.what());
    }
    units.push_back(std::move(u));
  }
  if (units.empty()) {
    err << "allanlot: error: no results file in " << opt.outdir.string() << " could be read\n";
    return kExitUsage;
  }
  const bool some_unreadable = !problems.empty();

  // Anchors: unique, deterministic (sorted file order), made of safe characters.
  std::set<std::string> used;
  for (Unit& u : units) {
    std::string a = "u-" + sanitize(u.rec.device_id);
    for (int k = 2; used.count(a); ++k)
      a = "u-" + sanitize(u.rec.device_id) + "-" + std::to_string(k);
    used.insert(a);
    u.anchor = a;
  }

  std::vector<fs::path> diag_files = others;
  diag_files.insert(diag_files.end(), opt.diagnosis_files.begin(), opt.diagnosis_files.end());
  for (const fs::path& f : diag_files) {
    try {
      attach_diagnoses(units, io::read_report_extras(f), f, err, opt.quiet, problems);
    } catch (const std::exception& e) {
      // Files given explicitly must be readable; stray files in OUTDIR (recordings kept beside
      // the results, say) need not be.
      const bool explicit_file = std::find(opt.diagnosis_files.begin(), opt.diagnosis_files.end(),
                                           f) != opt.diagnosis_files.end();
      if (explicit_file) {
        err << "allanlot: usage error: --diagnosis " << e.what() << "\n";
        return kExitUsage;
      }
    }
  }

  ExtrasMap extras;
  std::vector<FailedInput> failed_inputs;
  const fs::path summary = opt.outdir / "lot_summary.h5";
  if (fs::exists(summary, ec)) {
    try {
      read_lot_extras(io::read_summary_columns(summary), extras, failed_inputs);
    } catch (const std::exception& e) {
      problems.push_back(std::string("lot summary not used: ") + e.what());
    }
  }

  const fs::path output = opt.output.empty() ? opt.outdir / "report.html" : opt.output;
  const bool split = opt.unit_pages == UnitPages::Always ||
                     (opt.unit_pages == UnitPages::Auto &&
                      units.size() > static_cast<std::size_t>(kSinglePageMaxUnits));
  const std::string pages_dir = sanitize(output.stem().string()) + "_units";
  if (split) {
    std::set<std::string> names;
    for (Unit& u : units) {
      std::string n = sanitize(u.rec.device_id);
      for (int k = 2; names.count(n); ++k)
        n = sanitize(u.rec.device_id) + "-" + std::to_string(k);
      names.insert(n);
      u.page = pages_dir + "/" + n + ".html";
    }
  }

  const std::string title =
      "allanlot report: " + fs::absolute(opt.outdir).lexically_normal().filename().string();
  try {
    if (split) {
      const fs::path dir = output.parent_path() / pages_dir;
      fs::create_directories(dir, ec);
      if (ec) throw io::Error(dir.string(), "", "cannot create directory: " + ec.message());
      const std::string back = "../" + output.filename().string();
      for (const Unit& u : units) {
        std::string page = html_head("allanlot: " + u.rec.device_id);
        page += "<p class=\"small\"><a href=\"" + escape(back) + "#lot\">&larr; " + escape(title) +
                "</a></p>\n";
        page += unit_section(u, extras, back + "#lot");
        page += "</body>\n</html>\n";
        io::write_text_atomic(output.parent_path() / u.page, page);
      }
    }
    std::string html = html_head(title);
    html += lot_section(title, units, extras, failed_inputs, problems);
    if (!split)
      for (const Unit& u : units)
        html += unit_section(u, extras, "#lot");
    html += "</body>\n</html>\n";
    io::write_text_atomic(output, html);
    if (!opt.quiet)
      out << "report: " << output.string() << " (" << units.size() << " units"
          << (split ? ", unit pages in " + (output.parent_path() / pages_dir).string() : "")
          << ")\n";
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  return some_unreadable ? kExitSomeFailed : kExitOk;
}

Command add_report_command(CLI::App& app) {
  auto opt = std::make_shared<ReportOptions>();
  auto pages = std::make_shared<std::string>("auto");
  auto outdir = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto diag = std::make_shared<std::vector<std::string>>();
  auto* sub = app.add_subcommand(
      "report", "Write a self-contained HTML report (plots, tables) of analyze's results");
  sub->add_option("outdir", *outdir, "Output directory of analyze")->required();
  sub->add_option("-o,--output", *output, "HTML file to write (default: OUTDIR/report.html)");
  sub->add_option("--diagnosis", *diag,
                  "HDF5 files written by 'diagnose -o' to include (matched by device_id)");
  sub->add_option("--unit-pages", *pages,
                  "Per-unit pages beside the report: auto (above " +
                      std::to_string(kSinglePageMaxUnits) + " units), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->capture_default_str();
  sub->add_flag("-q,--quiet", opt->quiet, "Print only errors");
  return {sub, [=]() {
            opt->outdir = *outdir;
            opt->output = *output;
            opt->diagnosis_files.assign(diag->begin(), diag->end());
            opt->unit_pages = *pages == "always"  ? UnitPages::Always
                              : *pages == "never" ? UnitPages::Never
                                                  : UnitPages::Auto;
            return run_report(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
