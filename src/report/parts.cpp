#include "src/report/parts.hpp"

#include "kernels/allan/stats.hpp"
#include "kernels/model/units.hpp"
#include "src/lot/spec.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace allanlot::report {

using svg::escape;
using svg::number;

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
  if (out.empty()) out.push_back('_');  // not `out = "_"`: GCC 12 -Wrestrict false positive
  return out;
}

// Each statistic's colour, the same on every plot, is a fact of the statistic
// (kernels/allan/stats.hpp StatInfo::color).
std::string stat_color(const std::string& s) {
  const auto stat = kernels::parse_stat(s);
  if (!stat) throw std::invalid_argument("stat_color: no statistic '" + s + "'");
  return std::string(kernels::stat_info(*stat).color);
}

int term_index(const std::string& name) {
  for (std::size_t i = 0; i < kTerms.size(); ++i)
    if (name == kTerms[i].name) return static_cast<int>(i);
  return -1;
}

// The spellings the lot summary's writer uses (io/schema.cpp), and no others: a value it never
// writes is shown uncoloured rather than guessed at.
std::string spec_class(const std::string& v) {
  return v == "pass" || v == "fail" || v == "undecided" ? v : "";
}

std::string spec_cell(const RowExtras& x) {
  if (x.spec.empty()) return "";
  return escape(x.spec_detail.empty() ? x.spec : x.spec + ": " + x.spec_detail);
}

namespace {

// One term of a verdict's detail: the term, its estimate, the relation and the limit with its
// unit kept on one line; a trailing remark in parentheses ("(fit not within noise)") outside,
// where the cell may wrap before it.
std::string spec_term(const std::string& term) {
  const std::size_t remark = term.rfind(" (");
  if (term.empty() || term.back() != ')' || remark == std::string::npos || remark == 0)
    return "<span class=\"term\">" + escape(term) + "</span>";
  return "<span class=\"term\">" + escape(term.substr(0, remark)) + "</span> " +
         escape(term.substr(remark + 1));
}

}  // namespace

std::string spec_cell_terms(const RowExtras& x) {
  if (x.spec.empty()) return "";
  std::string out = "<b>" + escape(x.spec) + "</b>";
  std::size_t start = 0;
  for (bool first = true; start < x.spec_detail.size(); first = false) {
    const std::size_t end = std::min(x.spec_detail.find("; ", start), x.spec_detail.size());
    out += std::string(first ? ": " : "; ") + spec_term(x.spec_detail.substr(start, end - start));
    start = end + 2;
  }
  return out;
}

const RowExtras* unit_extras(const ExtrasMap& extras, const std::string& device_id) {
  for (auto it = extras.lower_bound({device_id, ""});
       it != extras.end() && it->first.first == device_id; ++it)
    if (!it->second.unit_spec.empty()) return &it->second;
  return nullptr;
}

namespace {

// fits_agree as read_summary_columns prints the stored i8: 1 agree, 0 not, -1 not compared.
std::string agree_value(const std::string& v) {
  return v == "1" ? "yes" : v == "0" ? "no" : "";
}

// A lot summary written before the unit columns (read with them empty) still has every
// channel's spec_status and term statuses: the units' verdicts are judged from those by the one
// rule, spec::judge_units.
void judge_units_of(const io::SummaryColumns& c, int dev, int chan, int spec,
                    const std::array<int, 5>& tspec, ExtrasMap& map) {
  const auto cell = [&](int column, std::size_t r) {
    return column < 0 ? std::string() : c.values[static_cast<std::size_t>(column)][r];
  };
  std::vector<io::SummaryRow> rows;
  for (std::size_t r = 0; r < c.rows; ++r) {
    io::SummaryRow row;
    row.device_id = cell(dev, r);
    row.channel = cell(chan, r);
    row.spec_status = cell(spec, r);
    if (row.channel.empty() && row.spec_status.empty()) row.spec_status = "no data";
    for (std::size_t t = 0; t < 5; ++t)
      row.spec_term_status[t] = cell(tspec[t], r);
    rows.push_back(std::move(row));
  }
  spec::judge_units(rows);
  for (const io::SummaryRow& row : rows)
    if (const auto it = map.find({row.device_id, row.channel}); it != map.end()) {
      it->second.unit_spec = spec_class(row.unit_spec_status);
      it->second.unit_spec_detail = row.unit_spec_detail;
    }
}

}  // namespace

void read_lot_extras(const io::SummaryColumns& c, ExtrasMap& map,
                     std::vector<FailedInput>& failed) {
  const int dev = c.find("device_id"), chan = c.find("channel"), status = c.find("status");
  if (dev < 0 || chan < 0) return;
  const int source = c.find("source_file");
  const auto col = [&](const std::string& a) { return c.find(a); };
  const int spec = col("spec_status"), agree = col("fits_agree");
  const int spec_detail = col("spec_detail"), unit_spec = col("unit_spec_status"),
            unit_detail = col("unit_spec_detail");
  const auto cell = [&](int column, std::size_t r) {
    return column < 0 ? std::string() : c.values[static_cast<std::size_t>(column)][r];
  };
  std::array<int, 5> tspec{};
  for (std::size_t t = 0; t < 5; ++t)
    tspec[t] = col(std::string(kTerms[t].name) + "_spec_status");
  bool any_spec = false, any_unit_spec = false;
  for (std::size_t r = 0; r < c.rows; ++r) {
    any_spec = any_spec || !cell(spec, r).empty();
    any_unit_spec = any_unit_spec || !cell(unit_spec, r).empty();
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
    x.spec_detail = cell(spec_detail, r);
    x.unit_spec = spec_class(cell(unit_spec, r));
    x.unit_spec_detail = cell(unit_detail, r);
    if (agree >= 0) x.agree = agree_value(c.values[static_cast<std::size_t>(agree)][r]);
    for (std::size_t t = 0; t < 5; ++t)
      if (tspec[t] >= 0)
        x.term_spec[t] = spec_class(c.values[static_cast<std::size_t>(tspec[t])][r]);
    map[{d, ch}] = x;
  }
  if (any_spec && !any_unit_spec) judge_units_of(c, dev, chan, spec, tspec, map);
}

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

std::string cell_number(double v, int digits) {
  std::string t = number(v, digits);
  // %g writes 130 as "1.3e+02" at 2 digits: below a million the plain integer reads better and
  // says the same (the value rounded to `digits` significant digits).
  if (t.find("e+") != std::string::npos && std::fabs(v) < 1e6) {
    const double step = std::pow(10.0, std::floor(std::log10(std::fabs(v))) - (digits - 1));
    t = number(std::round(v / step) * step, 7);
  }
  return t;
}

std::string value_pm(double v, double s) {
  if (std::isnan(v)) return "&ndash;";
  std::string t = cell_number(v, 3);
  if (std::isfinite(s) && s > 0) t += " &plusmn; " + cell_number(s, 2);
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

std::string AxisUnits::text() const {
  if (unit.empty()) return "no units given";
  if (unit == "1") return "dimensionless";
  return unit;
}

namespace {

AxisUnits axis_units(kernels::Term t, const std::string& channel_units) {
  if (channel_units.empty()) return {1.0, ""};
  const kernels::units::Datasheet d = kernels::units::to_datasheet(t, 1.0, channel_units);
  return {d.primary.value, d.primary.unit};
}

}  // namespace

AxisUnits rate_axis_units(const std::string& channel_units) {
  return axis_units(kernels::Term::B, channel_units);
}

AxisUnits time_error_axis_units(const std::string& channel_units) {
  return axis_units(kernels::Term::Q, channel_units);
}

bool is_clock(const std::string& channel_units) {
  return kernels::units::family_of(channel_units) == kernels::units::Family::Clock;
}

}  // namespace allanlot::report
