#include "src/report/parts.hpp"

#include "src/lot/statistics.hpp"
#include "src/report/svg.hpp"

#include <allanlot/version.hpp>

#include <algorithm>
#include <set>
#include <sstream>

namespace allanlot::report {

using svg::escape;
using svg::number;

namespace {

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

// "pass", or the detail when it starts with the status ("fail: gyro_x (N)"), else both
// ("undecided (no data: gyro_x)").
std::string unit_verdict_text(const RowExtras& x) {
  if (x.unit_spec_detail.empty()) return x.unit_spec;
  if (x.unit_spec_detail.starts_with(x.unit_spec + ":")) return x.unit_spec_detail;
  return x.unit_spec + " (" + x.unit_spec_detail + ")";
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
  if (any_spec) h << "<th class=\"l\">spec verdict</th>";
  if (any_agree) h << "<th>fits agree</th>";
  h << "</tr>\n";
  for (const Member& m : members) {
    const auto it = extras.find({m.unit->rec.device_id, channel});
    const RowExtras* x = it == extras.end() ? nullptr : &it->second;
    h << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(*m.unit, channel)) << "\">"
      << escape(m.unit->rec.device_id) << "</a></td>";
    // The status is words ("ok (fit: poor fit (chi2/dof = 709))"): it wraps between them, so
    // that the verdict stays in view.
    h << "<td class=\"l words" << (m.ch->status.is_ok() ? "" : " bad") << "\">"
      << escape(io::to_string(m.ch->status));
    if (m.ch->fit && m.ch->fit->status != kernels::FitStatus::Ok)
      h << " <span class=\"" << (m.ch->fit->model_within_noise == 1 ? "small" : "bad")
        << "\">(fit: " << escape(io::fit_status_text(*m.ch->fit)) << ")</span>";
    h << "</td>";
    for (std::size_t j = 0; j < 5; ++j) {
      const io::TermRecord* t = m.ch->fit ? find_term(*m.ch->fit, kTerms[j].name) : nullptr;
      std::string cls = x ? spec_class(x->term_spec[j]) : "";
      if (!t || !t->detected) cls += cls.empty() ? "nd" : " nd";
      h << "<td" << (cls.empty() ? "" : " class=\"" + cls + "\"") << ">";
      if (t) {
        h << (t->detected ? value_pm(t->value_datasheet, t->sigma_datasheet)
                          : "&lt; " + cell_number(t->upper_datasheet, 2));
        if (t->unit_datasheet != header_unit[j])
          h << " <span class=\"small\">" << escape(t->unit_datasheet) << "</span>";
      } else {
        h << "&ndash;";
      }
      h << "</td>";
    }
    h << "<td>" << (m.ch->fit ? cell_number(m.ch->fit->chi2_dof, 3) : "&ndash;") << "</td><td>"
      << (m.ch->crosscheck ? number(m.ch->crosscheck->max_abs_log10_ratio, 2) : "&ndash;")
      << "</td>";
    if (any_spec)
      h << "<td class=\"verdict" << (x && !x->spec.empty() ? " " + x->spec : std::string()) << "\">"
        << (x ? spec_cell_terms(*x) : std::string()) << "</td>";
    if (any_agree)
      h << "<td" << (x && x->agree == "no" ? " class=\"bad\"" : "") << ">" << (x ? x->agree : "")
        << "</td>";
    h << "</tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

// The channels of one kind across the lot: one channel path, units and data type.
struct ChannelGroup {
  std::string channel, units, data_type;
  std::vector<Member> members;
  std::string label() const {
    return channel + " (" + (units.empty() ? std::string("no units") : units) + ", " + data_type +
           " data)";
  }
};

// "rate (default)" is rate data too.
std::string data_kind(const std::string& data_type) {
  return data_type.rfind("phase", 0) == 0 ? "phase" : "rate";
}

void add_to_group(std::vector<ChannelGroup>& groups, const Member& m) {
  const std::string kind = data_kind(m.ch->data_type);
  for (ChannelGroup& g : groups)
    if (g.channel == m.ch->path && g.units == m.ch->units && g.data_type == kind) {
      g.members.push_back(m);
      return;
    }
  groups.push_back({m.ch->path, m.ch->units, kind, {m}});
}

// Ids stay "dist-<channel>" and "lot-<channel>" while a channel path has one group; the groups
// of a path shared by different kinds of channel add their units and data type.
std::string group_suffix(const std::vector<ChannelGroup>& groups, const ChannelGroup& g) {
  const auto n = std::count_if(groups.begin(), groups.end(),
                               [&](const ChannelGroup& o) { return o.channel == g.channel; });
  if (n <= 1) return std::string();
  // Appended piece by piece: GCC 12 at -O3 warns (-Wrestrict, a false positive) on the chain
  // of operator+ with a literal first.
  std::string suffix = "-";
  suffix += sanitize(g.units);
  suffix += '-';
  suffix += g.data_type;
  return suffix;
}

// The unit list with each unit's verdict (pass only when every channel passes) and, otherwise,
// which channel.
std::string units_nav(const std::vector<Unit>& units, const ExtrasMap& extras) {
  std::ostringstream h;
  h << "<nav class=\"units\"><b>Units:</b> ";
  for (const Unit& u : units) {
    std::size_t bad = 0;
    for (const auto& ch : u.rec.channels)
      bad += ch.status.is_ok() ? 0 : 1;
    h << "<a href=\"" << escape(unit_href(u)) << "\"" << (bad ? " class=\"bad\"" : "") << ">"
      << escape(u.rec.device_id);
    if (const RowExtras* x = unit_extras(extras, u.rec.device_id))
      h << " <span class=\"" << x->unit_spec << "\">" << escape(unit_verdict_text(*x)) << "</span>";
    h << "</a>";
  }
  h << "</nav>\n";
  return h.str();
}

// The lot's verdict as the lot summary's overview counts it: units, not channels. A unit passes
// when every channel a rule covers passes, fails when any fails, and is undecided otherwise
// (spec::judge_units, the one rule; its unit_spec_status is on every row of the unit). Units
// without a verdict (no rule covers them, or no data, a failed input among them) are counted
// apart. "" when the lot summary has no spec.
std::string unit_verdicts(const ExtrasMap& extras, const std::vector<FailedInput>& failed_inputs) {
  std::set<std::string> devices;
  for (const auto& [key, x] : extras)
    devices.insert(key.first);
  for (const FailedInput& f : failed_inputs)
    devices.insert(f.device_id);
  std::size_t pass = 0, fail = 0, undecided = 0, other = 0;
  for (const std::string& d : devices) {
    const RowExtras* x = unit_extras(extras, d);
    const std::string v = x ? x->unit_spec : "";
    (v == "pass" ? pass : v == "fail" ? fail : v == "undecided" ? undecided : other) += 1;
  }
  if (pass + fail + undecided == 0) return "";
  std::ostringstream h;
  h << "<p class=\"verdicts\"><b>Units against the spec:</b> <span class=\"pass\">" << pass
    << " pass</span> <span class=\"fail\">" << fail << " fail</span> <span class=\"undecided\">"
    << undecided << " undecided</span>";
  if (other > 0) h << " <span>" << other << " no spec or no data</span>";
  h << " <span class=\"small\">(a unit passes when every channel a rule covers passes, fails when "
       "any fails, and is undecided otherwise)</span></p>\n";
  return h.str();
}

}  // namespace

std::string lot_section(const std::string& title, const std::vector<Unit>& units,
                        const ExtrasMap& extras, const std::vector<FailedInput>& failed_inputs,
                        const std::vector<std::string>& problems) {
  std::ostringstream h;
  // Channels in the order of their first appearance across the (sorted) units, one group per
  // channel path, units and data type: devices of different kinds that share a channel name
  // (a clock's /data and a gyro's) are never pooled.
  std::vector<ChannelGroup> groups;
  std::size_t n_channels = 0, n_failed = 0;
  std::set<std::string> versions;
  std::string first_created, last_created;
  for (const Unit& u : units) {
    versions.insert(u.rec.tool_version);
    if (first_created.empty() || u.rec.created_utc < first_created)
      first_created = u.rec.created_utc;
    last_created = std::max(last_created, u.rec.created_utc);
    for (const auto& ch : u.rec.channels) {
      add_to_group(groups, {&u, &ch});
      ++n_channels;
      n_failed += ch.status.is_ok() ? 0 : 1;
    }
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
  h << "; report by allanlot " << escape(kVersion) << ".</p>\n"
    << unit_verdicts(extras, failed_inputs);
  if (!problems.empty() || !failed_inputs.empty()) {
    h << "<h2>Problems</h2>\n<ul>\n";
    for (const auto& p : problems)
      h << "<li class=\"bad\">" << escape(p) << "</li>\n";
    for (const auto& f : failed_inputs)
      h << "<li class=\"bad\">" << escape(f.device_id) << " (" << escape(f.source_file)
        << "): " << escape(f.status) << "</li>\n";
    h << "</ul>\n";
  }
  h << units_nav(units, extras);
  h << "<p class=\"small\">Values in datasheet units, &plusmn; 1&sigma;; grey: not detected "
       "(the 95 % upper bound is shown). Outliers, as in the lot summary: |value &minus; lot "
       "median| / &radic;(spread&sup2; + &sigma;&sup2;) above "
    << number(lot::kOutlierZ, 2) << ", spread = " << number(lot::kMadToSigma, 5)
    << " MAD, &sigma; the unit's own (at least " << lot::kMinUnitsForOutliers
    << " units, at least half of them detecting the term).</p>\n";
  const std::vector<Outlier> outliers = lot_outliers(units);
  std::ostringstream dists, tables;
  std::vector<std::string> without_terms;
  std::size_t n_clock_groups = 0;
  for (const ChannelGroup& g : groups) {
    const std::string suffix = group_suffix(groups, g);
    // Clocks (docs/clocks.md): each clock's power-law levels side by side, no distribution.
    const bool clocks = is_clock_channel(*g.members.front().ch);
    n_clock_groups += clocks ? 1 : 0;
    const std::string plot = clocks ? std::string()
                                    : distribution_plot("dist-" + sanitize(g.channel) + suffix,
                                                        g.label(), g.channel, g.members, outliers);
    if (plot.empty() && !clocks) without_terms.push_back(g.label());
    dists << plot;
    tables << "<div class=\"scroll\"><h3 id=\"lot-" << sanitize(g.channel) << suffix << "\">"
           << escape(g.label()) << "</h3>\n"
           << (clocks ? clock_summary_table(g.channel, g.members)
                      : summary_table(g.channel, g.members, extras))
           << "</div>\n";
  }
  h << "<h2>Distributions across units</h2>\n";
  if (n_clock_groups > 0)
    h << "<p class=\"small\">Clock channels are not pooled into distributions: each clock's "
         "power-law levels are in the summary by channel.</p>\n";
  if (n_clock_groups > 0 && n_clock_groups == groups.size()) {
    // Nothing to pool.
  } else if (without_terms.size() + n_clock_groups == groups.size()) {
    h << "<p>None: no unit has a fitted noise term (the results were analysed without the "
         "model fit, <code>--no-fit</code>).</p>\n";
  } else {
    h << "<p class=\"small\">Each detected term of each unit relative to the lot median "
         "(printed under its term with its datasheet unit), with the quartile box and 1.5 IQR "
         "whiskers; outliers in red link to the unit. One plot per channel, units and data "
         "type.</p>\n<div class=\"dists\">\n"
      << dists.str() << "</div>\n";
    if (!without_terms.empty()) {
      h << "<p class=\"small\">No detected term in: ";
      for (std::size_t i = 0; i < without_terms.size(); ++i)
        h << (i ? ", " : "") << escape(without_terms[i]);
      h << ".</p>\n";
    }
  }
  h << quality_section(units);
  h << diagnoses_section(units);
  h << "<h2>Outlier units</h2>\n";
  if (without_terms.size() + n_clock_groups == groups.size()) {
    h << "<p>None: no fitted terms to compare.</p>\n";
  } else if (outliers.empty()) {
    h << "<p>None.</p>\n";
  } else {
    h << "<table><tr><th class=\"l\">unit</th><th class=\"l\">channel</th><th>term</th>"
         "<th>value</th><th class=\"l\">unit</th><th>/ lot median</th><th>modified z</th></tr>\n";
    for (const Outlier& o : outliers)
      h << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(*o.unit, o.channel)) << "\">"
        << escape(o.unit->rec.device_id) << "</a></td><td class=\"l\">" << escape(o.channel)
        << "</td><td>" << kTerms[o.term].name << "</td><td>" << number(o.value, 3)
        << "</td><td class=\"l\">" << escape(o.unit_ds) << "</td><td>" << number(o.ratio, 3)
        << "</td><td>" << escape(lot::z_text(o.z)) << "</td></tr>\n";
    h << "</table>\n";
  }
  h << "<h2>Summary by channel</h2>\n<div class=\"tables\">\n"
    << tables.str() << "</div>\n</section>\n";
  return h.str();
}

}  // namespace allanlot::report
