#include "src/report/parts.hpp"

#include "kernels/allan/stats.hpp"
#include "src/report/svg.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace allanlot::report {

using svg::escape;
using svg::number;

// ---------------------------------------------------------------------------------------------
// HTML.

namespace {

// Plots sit in a grid of at least 520 px columns, the tables below them. A table cell never
// breaks inside a number, a unit or a name ("unit_00" over "01", "mg/sqrt(" over "h)" read as
// other values): data cells do not wrap at all; headings, statuses and the verdict's sentences
// wrap only between words; only the free-text cells of a diagnosis (JSON attributes) may break
// a word too long for their 900 px. The lot's summary tables, the widest, sit in a box that
// scrolls sideways rather than widen the page in a window narrower than they are (they fit
// from 1280 px: tests/browser/check_report.py).
const char* kCss =
    R"(body{font:14px/1.45 Helvetica,Arial,sans-serif;color:#222;margin:0 auto;max-width:1600px;padding:0 18px 40px}
h1{font-size:24px;margin:18px 0 6px}h2{font-size:19px;border-bottom:2px solid #ccc;padding-bottom:3px;margin-top:28px}
h3{font-size:16px;margin:22px 0 6px}h4{font-size:14px;margin:12px 0 4px}
table{border-collapse:collapse;margin:6px 0 14px;font-size:13px;max-width:100%}
th,td{border:1px solid #ccc;padding:2px 7px;text-align:right;vertical-align:top}td{white-space:nowrap}
th{background:#f1f1f1}td.l,th.l{text-align:left}td.wrap{white-space:normal;max-width:900px;word-break:break-word;font-size:12px}
td.words{white-space:normal;min-width:7em}td.verdict{white-space:normal;text-align:left;min-width:16em;max-width:30em}.verdict .term{white-space:nowrap}
.scroll{overflow-x:auto;max-width:100%}
.pass{background:#cdeccf}.fail{background:#f6c4c4}.undecided{background:#fbeab5}
.nd{color:#999}.bad{color:#b00;font-weight:bold}.small{font-size:12px;color:#555}
.plots{display:grid;grid-template-columns:repeat(auto-fill,minmax(520px,1fr));gap:10px;margin:6px 0}
.plots>*{min-width:0}
.panel{border:1px solid #e4e4e4;padding-top:3px}.panel>svg.plot{border:0}.panel>span.small{margin:0 6px}
.panel>label{font-size:12px;margin-right:10px;white-space:nowrap}.panel>input{margin:0 3px 0 0;vertical-align:middle}
.sw{display:inline-block;width:10px;height:10px;margin-right:3px;vertical-align:middle}
svg.plot{width:100%;height:auto;display:block;border:1px solid #e4e4e4;box-sizing:border-box}
.dists{display:grid;grid-template-columns:repeat(auto-fill,minmax(420px,1fr));gap:10px}
.tables{display:flex;flex-wrap:wrap;gap:0 28px;align-items:flex-start}.tables>*{max-width:100%}
.tables>.fig{flex:1 1 560px;max-width:780px}
details.devtables>summary{cursor:pointer;margin:4px 0}table.dev caption{font-weight:bold;text-align:left}
nav.units a{display:inline-block;margin:0 10px 2px 0}
.legend-key span{display:inline-block;padding:0 8px;margin-right:6px;border:1px solid #ccc}
@media print{.plots{grid-template-columns:1fr 1fr}section.unit{break-before:page}}
)";

}  // namespace

std::string html_head(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta "
         "name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         escape(title) + "</title>\n<style>\n" + kCss + toggle_css() +
         "</style>\n</head>\n<body>\n";
}

namespace {

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
      h << "<br><span class=\"small\">= " << cell_number(t->value_datasheet_alt, 3) << " "
        << escape(t->unit_datasheet_alt) << "</span>";
    h << "</td><td>";
    if (t->detected)
      h << "yes";
    else
      h << "<span class=\"nd\">no, &lt; "
        << (std::isfinite(t->upper_datasheet) ? cell_number(t->upper_datasheet, 2) : "?")
        << "</span>";
    h << "</td>";
    if (psd_fit) {
      const io::TermRecord* q = find_term(*psd_fit, kTerms[j].name);
      h << "<td>" << (q ? value_pm(q->value_datasheet, q->sigma_datasheet) : std::string("&ndash;"))
        << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

// The notes of diagnose's JSON report (the group's `report` attribute, docs/diagnose.md): why a
// look-alike was passed over, an effect pruned, the coefficients re-estimated. None when the
// attribute is missing or not that JSON.
std::vector<std::string> diagnose_notes(const io::DiagnosisView& d) {
  std::vector<std::string> out;
  for (const auto& [k, v] : d.attributes) {
    if (k != "report") continue;
    const nlohmann::json j = nlohmann::json::parse(v, nullptr, false);
    if (!j.is_object() || !j.contains("notes") || !j["notes"].is_array()) continue;
    for (const auto& n : j["notes"])
      if (n.is_string()) out.push_back(n.get<std::string>());
  }
  return out;
}

// An iteration's parameters ({"parameters": {name: value}, "sigmas": {name: sigma or null}},
// src/workflow/diagnosis_json.hpp) as "name = value ± sigma" lines; the text as it is otherwise.
std::string parameters_html(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("parameters") || !j["parameters"].is_object())
    return escape(text);
  const nlohmann::json sigmas = j.value("sigmas", nlohmann::json::object());
  std::string out;
  for (const auto& [name, value] : j["parameters"].items()) {
    if (!value.is_number()) continue;
    out += (out.empty() ? "" : "<br>") + escape(name) + " = " + number(value.get<double>(), 4);
    if (sigmas.contains(name) && sigmas[name].is_number())
      out += " &plusmn; " + number(sigmas[name].get<double>(), 2);
  }
  return out;
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
    h << "<table><tr><th>round</th><th class=\"l\">effect</th><th>gap before</th>"
         "<th>gap after</th><th>&Delta;IC</th><th class=\"l\">parameters</th></tr>\n";
    const auto num = [](const std::vector<double>& v, std::size_t i) {
      return i < v.size() ? number(v[i], 3) : std::string("&ndash;");
    };
    for (std::size_t i = 0; i < iterations; ++i)
      h << "<tr><td>" << i + 1 << "</td><td class=\"l\">"
        << (i < d.effects_named.size() ? escape(d.effects_named[i]) : std::string()) << "</td><td>"
        << num(d.iteration_gap_before, i) << "</td><td>" << num(d.iteration_gap_after, i)
        << "</td><td>" << num(d.iteration_delta_ic, i) << "</td><td class=\"l wrap\">"
        << (i < d.iteration_parameters.size() ? parameters_html(d.iteration_parameters[i])
                                              : std::string())
        << "</td></tr>\n";
    h << "</table>\n";
  }
  for (const std::string& n : diagnose_notes(d))
    h << "<p class=\"small\">" << escape(n) << "</p>\n";
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

// The read-outs datasheets quote (IEEE Std 952 annex C, fit/readouts), under the coefficients:
// given whether or not the fit detects the term, and marked when it does not.
std::string readout_table(const io::FitRecord& fit) {
  if (fit.readouts.empty()) return "";
  std::ostringstream h;
  h << "<table class=\"coef\"><tr><th>read-out</th><th>value</th><th>unit</th><th>&tau;</th>"
       "</tr>\n";
  for (const io::ReadoutRecord& r : fit.readouts) {
    const bool alt = !r.unit_datasheet_alt.empty();
    const char* label = r.name == "N_1s"               ? "N at 1 s"
                        : r.name == "bias_instability" ? "B: min / 0.664"
                                                       : "K at 3 s";
    h << "<tr><td class=\"l\">" << label << "</td><td" << (r.valid ? "" : " class=\"nd\"") << ">"
      << cell_number(alt ? r.value_datasheet_alt : r.value_datasheet, 3) << " &plusmn; "
      << cell_number(alt ? r.sigma_datasheet_alt : r.sigma_datasheet, 2) << (r.valid ? "" : " *")
      << "</td><td>" << escape(alt ? r.unit_datasheet_alt : r.unit_datasheet) << "</td><td>"
      << cell_number(r.tau_s, 3) << " s</td></tr>\n";
  }
  h << "</table>\n<p class=\"small\">* the fit does not detect this term: the read-out reads a "
       "branch the curve may not have.</p>\n";
  return h.str();
}

// Every statistic's table, folded away (a channel has a few hundred rows): tau, the number of
// terms, the noise exponent and the deviation with its interval, in the plots' units.
std::string deviation_tables(const std::string& id, const io::ChannelResult& ch) {
  if (ch.stats.empty()) return "";
  std::ostringstream h, names;
  for (const auto& [name, s] : ch.stats) {
    const auto stat = kernels::parse_stat(name);
    const bool te = stat && kernels::is_time_error(*stat);
    const AxisUnits u = te ? time_error_axis_units(ch.units) : rate_axis_units(ch.units);
    names << (names.tellp() > 0 ? ", " : "") << escape(name);
    const bool ci = s.dev_lo.size() == s.size() && s.dev_hi.size() == s.size();
    h << "<table class=\"dev\" id=\"" << id << "-dev-" << sanitize(name) << "\"><caption>"
      << escape(name) << " (" << escape(u.text()) << ")</caption>\n<tr><th>&tau; (s)</th><th>n</th>"
      << "<th>&alpha;</th>" << (ci ? "<th>lower</th>" : "") << "<th>" << escape(name) << "</th>"
      << (ci ? "<th>upper</th>" : "") << "</tr>\n";
    for (std::size_t i = 0; i < s.size() && i < s.dev.size(); ++i) {
      h << "<tr><td>" << cell_number(s.tau_s[i], 4) << "</td><td>"
        << (i < s.n.size() ? std::to_string(s.n[i]) : "") << "</td><td>"
        << (i < s.alpha.size() ? noise_type_label(s.alpha[i]) : "") << "</td>";
      if (ci) h << "<td>" << number(s.dev_lo[i] * u.factor, 4) << "</td>";
      h << "<td>" << number(s.dev[i] * u.factor, 4) << "</td>";
      if (ci) h << "<td>" << number(s.dev_hi[i] * u.factor, 4) << "</td>";
      h << "</tr>\n";
    }
    h << "</table>\n";
  }
  return "<details class=\"devtables\" id=\"" + id + "-devtables\"><summary>Deviation tables (" +
         names.str() + ")</summary>\n<div class=\"tables\">\n" + h.str() + "</div></details>\n";
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
    << " gaps";
  // What the gap policy did (docs/statistics.md "Gaps"); the note below says it in full.
  if (ch.n_gaps > 0 && !ch.gap_policy.empty())
    h << " (" << ch.n_filled << " filled, " << escape(ch.gap_policy) << ")";
  h << ", " << escape(ch.data_type) << " data";
  if (is_clock(ch.units)) h << " (deviations of the fractional frequency, dimensionless)";
  if (ch.fit) {
    h << "; fit " << escape(io::fit_status_text(*ch.fit)) << ", &chi;&sup2;/dof "
      << number(ch.fit->chi2_dof, 3);
    if (!ch.fit->model.empty())
      h << " (eq. (3) alone; the coefficients and the curve drawn are those of the model, gap "
        << number(ch.fit->model_gap, 3) << " against its " << ch.fit->model_replicas
        << " replicas' p95 " << number(ch.fit->model_gap_p95, 3) << ")";
    else if (ch.fit->status == kernels::FitStatus::PoorFit)
      h << " (the model misses part of the curve: <code>allanlot diagnose</code> names what)";
    // The taus the sensor's filter left out of the fit (docs/fit-and-psd.md).
    if (!ch.fit->tau.empty() && ch.fit->first_tau_fitted > ch.fit->tau.front())
      h << "; fitted from &tau; = " << number(ch.fit->first_tau_fitted, 3)
        << " s (the sensor's low-pass filter acts below; " << escape(ch.fit->lowpass)
        << "; all taus: &chi;&sup2;/dof " << number(ch.fit->chi2_dof_all_taus, 3) << ")";
  }
  // A clock's page speaks of its PSD cross-check, not of the paper's eq. (2) (docs/clocks.md).
  if (ch.crosscheck)
    h << (is_clock_channel(ch) ? "; PSD cross-check" : "; eq. (2)") << " max |log&#8321;&#8320; "
      << "ratio| " << number(ch.crosscheck->max_abs_log10_ratio, 3);
  if (x && !x->spec.empty())
    h << "; spec: <span class=\"" << x->spec << "\">" << spec_cell(*x) << "</span>";
  if (x && x->agree == "no") h << "; <span class=\"bad\">time- and PSD-domain fits disagree</span>";
  h << "</p>\n";
  if (!ch.status.is_ok()) h << "<p class=\"bad\">" << escape(io::to_string(ch.status)) << "</p>\n";
  if (ch.quality) h << quality_line(*ch.quality, ch.sample_rate_hz);
  if (!ch.notes.empty()) h << "<p class=\"small\">Notes: " << escape(ch.notes) << "</p>\n";
  if (ch.status.is_ok()) {
    // Only the panels whose part was computed: no empty frame for a --no-psd or --no-fit run.
    h << "<div class=\"plots\">\n"
      << deviation_panel(id + "-adev", ch, false)
      << deviation_panel(id + "-tdev", ch, true,
                         u.masks.contains(ch.path) ? u.masks.at(ch.path)
                                                   : std::vector<const masks::Mask*>{});
    if (ch.psd && !ch.psd->f.empty()) h << psd_plot(id + "-psd", ch, psd_fit);
    if (ch.crosscheck && !ch.crosscheck->tau.empty())
      h << crosscheck_plot(id + "-xc", *ch.crosscheck, is_clock_channel(ch));
    h << "</div>\n";
    // The tables under the plots, at their own width, wrapping rather than scrolling.
    if (ch.fit && !ch.fit->terms.empty())
      h << "<div class=\"tables\"><div><h4>Equation (3) coefficients (datasheet units)</h4>\n"
        << coefficient_table(ch, psd_fit, x) << "</div><div><h4>Read-outs</h4>\n"
        << readout_table(*ch.fit) << "</div></div>\n";
    if (ch.powerlaw)
      h << "<div class=\"tables\"><div><h4>Power-law noise levels</h4>\n"
        << powerlaw_table_html(ch) << "</div><div class=\"fig\">"
        << powerlaw_residual_plot(id + "-res", ch) << "</div></div>\n";
    h << deviation_tables(id, ch);
    h << editing_section(id, ch);
  }
  const auto d = u.diagnoses.find(ch.path);
  if (d != u.diagnoses.end()) h << diagnosis_section(id + "-diag", d->second, ch.units);
  h << "</section>\n";
  return h.str();
}

}  // namespace

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
  h << hat_section(u);  // a hat's results: its clocks together (clocks.cpp)
  for (const auto& ch : u.rec.channels)
    h << channel_section(u, ch, extras);
  h << "</section>\n";
  return h.str();
}

}  // namespace allanlot::report
