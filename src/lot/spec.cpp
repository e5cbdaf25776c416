// Spec file parsing and the pass/fail decisions; the rules are listed in spec.hpp.
#include "src/lot/spec.hpp"

#include "io/stat_group.hpp"
#include "kernels/uncertainty/chi2.hpp"
#include "src/lot/masks.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fnmatch.h>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace allanlot::spec {

namespace {

using Json = nlohmann::ordered_json;  // ordered: the first matching rule in file order wins
namespace units = kernels::units;

// Checks one JSON document against the spec schema, collecting every problem rather than
// stopping at the first, so that one run names all a spec's mistakes (docs/lots-and-slurm.md).
// Each message is "<source>: <key path>: <reason>". note() records a problem and carries on;
// fail() records one and abandons the value being checked (thrown as Skip, caught by
// Checker::each around the next enclosing value), since nothing inside it can be read.
class Checker {
public:
  struct Skip {};

  explicit Checker(std::string source) : source_(std::move(source)) {}

  void note(const std::string& path, const std::string& reason) const {
    errors_.push_back(source_ + ": " + (path.empty() ? std::string() : path + ": ") + reason);
  }
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    note(path, reason);
    throw Skip{};
  }
  // Runs `check` on one value; a fail() inside it ends that value only.
  template <class F>
  void each(F&& check) const {
    try {
      check();
    } catch (const Skip&) {
    }
  }
  // Throws the spec::Error of every problem noted: one alone as it is, several under a line
  // that counts them.
  void throw_if_any() const {
    if (!errors_.empty()) throw combined_error(source_, errors_);
  }

  static std::string at(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  const Json& object(const Json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, std::string("must be an object, not ") + j.type_name());
    return j;
  }

  void allow(const Json& j, std::initializer_list<std::string_view> keys,
             const std::string& path) const {
    for (const auto& [key, value] : j.items())
      if (std::find(keys.begin(), keys.end(), key) == keys.end())
        note(at(path, key), "unknown key");
  }

  std::optional<double> limit(const Json& j, const std::string& path) const {
    if (!j.is_number()) {
      note(path, std::string("must be a number, not ") + j.type_name());
      return std::nullopt;
    }
    const double v = j.get<double>();
    if (!std::isfinite(v)) {
      note(path, "must be finite");
      return std::nullopt;
    }
    if (v < 0) {
      note(path, "must be >= 0, got " + j.dump());
      return std::nullopt;
    }
    return v;
  }

private:
  std::string source_;
  mutable std::vector<std::string> errors_;
};

// The channel units whose datasheet forms a spec may use (kernels/model/units.hpp and
// docs/formats.md "Input recordings"). A unit string outside these is not knowable before the data
// are seen.
constexpr std::string_view kKnownChannelUnits[] = {"deg/s", "deg/h", "rad/s", "m/s^2", "g",
                                                   "mg",    "ug",    "s",     "1"};

// In any spelling of the one vocabulary (units::normalize_spelling): "deg/√hr" is deg/sqrt(h).
bool is_unit_of(units::Term t, const std::string& unit) {
  const std::string spelled = units::normalize_spelling(unit);
  for (std::string_view cu : kKnownChannelUnits)
    for (const std::string& ok : units::accepted_units(t, cu))
      if (units::normalize_spelling(ok) == spelled) return true;
  return false;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v)
    s += (s.empty() ? "" : ", ") + x;
  return s;
}

// One term's limits; every problem of it is noted (a bad max does not hide a bad unit).
TermLimit parse_limit(const Checker& c, units::Term term, const Json& j, const std::string& path) {
  c.object(j, path);
  c.allow(j, {"max", "min", "unit"}, path);
  TermLimit l;
  l.term = term;
  l.key_path = path;
  if (j.contains("max")) l.max = c.limit(j["max"], Checker::at(path, "max"));
  if (j.contains("min")) l.min = c.limit(j["min"], Checker::at(path, "min"));
  if (!j.contains("max") && !j.contains("min")) c.note(path, "needs \"max\", \"min\" or both");
  if (l.max && l.min && *l.min > *l.max)
    c.note(Checker::at(path, "min"),
           "must not exceed max (" + j["max"].dump() + "), got " + j["min"].dump());
  const auto u = j.find("unit");
  if (u == j.end()) {
    c.note(Checker::at(path, "unit"), "missing");
  } else if (!u->is_string()) {
    c.note(Checker::at(path, "unit"), "must be a string");
  } else {
    l.unit = u->get<std::string>();
    if (!is_unit_of(term, l.unit)) {
      auto datasheet = units::accepted_units(term, "deg/s");
      for (const auto& a : units::accepted_units(term, "m/s^2"))
        datasheet.push_back(a);
      c.note(Checker::at(path, "unit"), "'" + l.unit + "' is not a unit of " +
                                            std::string(units::term_name(term)) + " (e.g. " +
                                            join(datasheet) + ")");
    }
  }
  return l;
}

// The quality keys of a rule: a count's limit, or a flag's "fail" / "ignore" (docs/quality.md).
struct QualityKey {
  const char* max_key;   // "max_spikes"
  const char* flag_key;  // "spikes", or nullptr
  std::optional<std::int64_t> QualityLimits::*member;
};
constexpr QualityKey kQualityKeys[] = {
    {"max_gaps", "gaps", &QualityLimits::max_gaps},
    {"max_missing", nullptr, &QualityLimits::max_missing},
    {"max_spikes", "spikes", &QualityLimits::max_spikes},
    {"max_saturated", "saturation", &QualityLimits::max_saturated},
    {"max_stuck", "stuck", &QualityLimits::max_stuck},
    {"max_time_errors", "time_stamps", &QualityLimits::max_time_errors},
};

// One key of a "quality" object into `q`; `seen` holds the counts given so far.
void parse_quality_key(const Checker& c, const std::string& key, const Json& value,
                       const std::string& at, QualityLimits& q, std::set<const QualityKey*>& seen) {
  const QualityKey* k = nullptr;
  for (const QualityKey& cand : kQualityKeys)
    if (key == cand.max_key || (cand.flag_key && key == cand.flag_key)) k = &cand;
  if (!k)
    c.fail(at, "unknown key (max_gaps, max_missing, max_spikes, max_saturated, max_stuck, "
               "max_time_errors, gaps, spikes, saturation, stuck, time_stamps)");
  if (!seen.insert(k).second)  // the other spelling of the same count came first
    c.fail(at, std::string("give ") + k->max_key + " or " + k->flag_key + ", not both");
  if (key == k->max_key) {
    if (!value.is_number_integer() || value.get<std::int64_t>() < 0)
      c.fail(at, "must be an integer >= 0, got " + value.dump());
    q.*(k->member) = value.get<std::int64_t>();
  } else if (value == "fail") {
    q.*(k->member) = 0;
  } else if (value != "ignore") {
    c.fail(at, "must be \"fail\" or \"ignore\", got " + value.dump());
  }
}

QualityLimits parse_quality(const Checker& c, const Json& j, const std::string& path) {
  c.object(j, path);
  if (j.empty()) c.fail(path, "must limit at least one quality count");
  QualityLimits q;
  q.key_path = path;
  std::set<const QualityKey*> seen;
  // Plain variables, not a structured binding: clang 14 (the TSan build) cannot capture one.
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    const Json& value = item.value();
    c.each([&] { parse_quality_key(c, key, value, Checker::at(path, key), q, seen); });
  }
  return q;
}

// The detail prints values to 3 significant digits and half-widths to 2 (the half-width's
// leading digits decide how many of the value's mean anything), limits as the spec wrote them
// up to 4 (a limit of 0.04929 mg/sqrt(Hz) must not look moved).
std::string number(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// An unclosed '[' leaves fnmatch(3) free to match it literally or not at all (POSIX leaves it
// open): such a pattern cannot be meant, so it is refused rather than silently match nothing.
bool glob_well_formed(const std::string& glob) {
  for (std::size_t i = 0; i < glob.size(); ++i) {
    if (glob[i] == '\\') {
      ++i;
    } else if (glob[i] == '[') {
      std::size_t j = i + 1;
      if (j < glob.size() && (glob[j] == '!' || glob[j] == '^')) ++j;
      if (j < glob.size() && glob[j] == ']') ++j;  // "[]...]": the first ']' is a member
      while (j < glob.size() && glob[j] != ']')
        ++j;
      if (j == glob.size()) return false;
      i = j;
    }
  }
  return true;
}

// "mtie": {"mask": "G.811"}: a mask of src/lot/masks.hpp for that statistic.
MaskLimit parse_mask(const Checker& c, const std::string& stat, const Json& j,
                     const std::string& path) {
  c.object(j, path);
  c.allow(j, {"mask"}, path);
  const auto m = j.find("mask");
  if (m == j.end()) c.fail(Checker::at(path, "mask"), "missing");
  if (!m->is_string()) c.fail(Checker::at(path, "mask"), "must be a string");
  const std::string name = m->get<std::string>();
  if (!masks::find_mask(name, stat))
    c.fail(Checker::at(path, "mask"),
           "no " + stat + " mask '" + name + "' (masks: " + masks::mask_names(stat) + ")");
  return {stat, name, path};
}

// One rule: every term and the quality limits, each checked on its own.
Rule parse_rule(const Checker& c, const std::string& glob, const Json& body,
                const std::string& path) {
  Rule r;
  r.glob = glob;
  if (glob.empty()) c.note(path, "empty channel pattern");
  if (!glob_well_formed(glob)) c.note(path, "unknown channel pattern: '[' without its ']'");
  c.object(body, path);
  if (body.empty())
    c.fail(path, "must limit at least one term (R, K, B, N or Q), quality, mtie or tdev");
  for (const auto& item : body.items()) {
    const std::string& key = item.key();
    const Json& value = item.value();
    const std::string at = Checker::at(path, key);
    c.each([&] {
      if (key == "quality") {
        r.quality = parse_quality(c, value, at);
        return;
      }
      if (key == "mtie" || key == "tdev") {
        r.masks.push_back(parse_mask(c, key, value, at));
        return;
      }
      const auto term = units::parse_term(key);
      if (!term) c.fail(at, "unknown key (the terms are R, K, B, N, Q; and quality, mtie, tdev)");
      r.limits.push_back(parse_limit(c, *term, value, at));
    });
  }
  return r;
}

// Parses the JSON into `nlohmann` form, noting every duplicate key: JSON leaves their meaning
// open and nlohmann keeps the last one silently, so a limit that depends on that is refused.
// Each open object keeps its keys and the key it was opened under, so the message names the
// whole path.
Json parse_json(const Checker& c, std::string_view json_text) {
  struct Open {
    std::string path;
    std::set<std::string> keys;
  };
  std::vector<Open> open;
  std::string last_key;
  std::vector<std::string> duplicates;
  const Json::parser_callback_t cb = [&](int, Json::parse_event_t ev, Json& parsed) {
    if (ev == Json::parse_event_t::object_start)
      open.push_back({open.empty() ? std::string() : Checker::at(open.back().path, last_key), {}});
    else if (ev == Json::parse_event_t::object_end && !open.empty())
      open.pop_back();
    else if (ev == Json::parse_event_t::key && !open.empty()) {
      last_key = parsed.get<std::string>();
      if (!open.back().keys.insert(last_key).second)
        duplicates.push_back(Checker::at(open.back().path, last_key));
    }
    return true;
  };
  Json root;
  try {
    root = Json::parse(json_text.begin(), json_text.end(), cb);
  } catch (const Json::exception& e) {
    c.fail("", std::string("invalid JSON: ") + e.what());
  }
  for (const std::string& d : duplicates)
    c.note(d, "duplicate key");
  return root;
}

// The whole document into `s`; every problem is noted on `c`.
void check_document(const Checker& c, std::string_view json_text, Spec& s) {
  const Json root = parse_json(c, json_text);
  c.object(root, "");
  c.allow(root, {"name", "confidence", "channels"}, "");
  c.each([&] {
    if (!root.contains("name")) return;
    if (!root["name"].is_string()) c.fail("name", "must be a string");
    s.name = root["name"].get<std::string>();
  });
  c.each([&] {
    if (!root.contains("confidence")) return;
    const Json& j = root["confidence"];
    if (!j.is_number()) c.fail("confidence", std::string("must be a number, not ") + j.type_name());
    if (!(j.get<double>() > 0.0 && j.get<double>() < 1.0))
      c.fail("confidence", "must be in (0, 1), got " + j.dump());
    s.confidence = j.get<double>();
  });
  s.k = two_sided_normal_quantile(s.confidence);
  const auto chans = root.find("channels");
  if (chans == root.end()) c.fail("channels", "missing");
  c.object(*chans, "channels");
  if (chans->empty()) c.fail("channels", "must not be empty");
  for (const auto& item : chans->items()) {
    const std::string& glob = item.key();
    const Json& body = item.value();
    c.each([&] { s.rules.push_back(parse_rule(c, glob, body, Checker::at("channels", glob))); });
  }
}

}  // namespace

Error combined_error(const std::string& source, std::vector<std::string> messages) {
  if (messages.size() == 1) {
    const std::string one = messages.front();  // copied: the vector is moved below
    return Error(one, std::move(messages));
  }
  std::string all = source + ": " + std::to_string(messages.size()) + " errors:";
  for (const std::string& m : messages)
    all += "\n  " + m;
  return Error(all, std::move(messages));
}

double two_sided_normal_quantile(double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("confidence must be in (0, 1), got " + std::to_string(confidence));
  return std::sqrt(kernels::chi2_quantile(confidence, 1.0));
}

Spec parse_spec(std::string_view json_text, const std::string& source) {
  const Checker c(source);
  Spec s;
  s.source = source;
  c.each([&] { check_document(c, json_text, s); });
  c.throw_if_any();
  return s;
}

Spec load_spec(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open the spec file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(path.string() + ": cannot read the spec file");
  return parse_spec(text.str(), path.string());
}

const Rule* find_rule(const Spec& spec, const std::string& channel_path) {
  const std::string name = channel_path.substr(channel_path.find_last_of('/') + 1);
  for (const Rule& r : spec.rules)
    if (fnmatch(r.glob.c_str(), channel_path.c_str(), 0) == 0 ||
        fnmatch(r.glob.c_str(), name.c_str(), 0) == 0)
      return &r;
  return nullptr;
}

double convert(units::Term t, double value, std::string_view from_unit, std::string_view to_unit,
               std::string_view channel_units) {
  const double own = units::from_datasheet(t, value, from_unit, channel_units);
  if (to_unit == units::channel_unit(t, channel_units)) return own;
  const units::Datasheet d = units::to_datasheet(t, own, channel_units);
  if (d.primary.unit == to_unit) return d.primary.value;
  if (d.secondary && d.secondary->unit == to_unit) return d.secondary->value;
  throw std::invalid_argument("units: " + std::string(units::term_name(t)) + " of a '" +
                              std::string(channel_units) + "' channel cannot be given in '" +
                              std::string(to_unit) + "'");
}

std::pair<double, double> interval(const Estimate& e, double k) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (!std::isfinite(e.sigma)) return {0.0, inf};
  if (e.detected) return {std::max(0.0, e.value - k * e.sigma), e.value + k * e.sigma};
  return {0.0, std::isfinite(e.upper) ? e.upper : e.value + k * e.sigma};
}

Outcome decide(const Estimate& e, std::optional<double> min, std::optional<double> max, double k) {
  const auto [lo, hi] = interval(e, k);
  Outcome o = Outcome::Pass;
  const auto merge = [&o](Outcome x) {
    if (x == Outcome::Fail || (x == Outcome::Undecided && o == Outcome::Pass)) o = x;
  };
  if (max) merge(hi <= *max ? Outcome::Pass : lo > *max ? Outcome::Fail : Outcome::Undecided);
  if (min) merge(lo >= *min ? Outcome::Pass : hi < *min ? Outcome::Fail : Outcome::Undecided);
  return o;
}

namespace {

// The estimate as the detail quotes it: in the unit the spec wrote the limit in, beside the
// limit as written, so that a limit on ARW in deg/sqrt(h) reads against N in deg/sqrt(h). The
// datasheet forms of a term differ by exact factors (kernels/model/units.hpp): one spec unit is
// `f` row units.
std::string quoted_estimate(const TermLimit& l, const Estimate& e, double k,
                            const std::string& row_unit, const std::string& channel_units) {
  const double f = convert(l.term, 1.0, l.unit, row_unit, channel_units);
  return e.detected || !std::isfinite(e.upper)
             ? number(e.value / f, 3) + "±" + number(k * e.sigma / f, 2)
             : "<" + number(e.upper / f, 3);
}

Verdict judge_terms(const Spec& spec, const io::SummaryRow& row) {
  const bool any_value =
      std::any_of(row.value.begin(), row.value.end(), [](double v) { return std::isfinite(v); });
  if (!row.status.is_ok() || row.channel.empty()) return {"no data", "", {}};  // status says why
  if (!any_value) return {"no data", "no fitted value", {}};
  const Rule* rule = find_rule(spec, row.channel);
  if (!rule) return {"no spec", "", {}};
  const auto outcome_name = [](Outcome o) {
    return o == Outcome::Pass ? "pass" : o == Outcome::Fail ? "fail" : "undecided";
  };
  Verdict v;
  std::vector<std::pair<Outcome, std::string>> terms;
  std::vector<std::string> unit_errors;  // every limit whose unit does not fit this channel
  for (const TermLimit& l : rule->limits) {
    const auto i = static_cast<std::size_t>(l.term);
    const std::string name(units::term_name(l.term));
    if (!std::isfinite(row.value[i]) || row.unit[i].empty()) {
      terms.emplace_back(Outcome::Undecided, name + " no estimate");
      v.term_status[i] = outcome_name(Outcome::Undecided);
      continue;
    }
    // The decision is made in the row's datasheet unit, on the values exactly as the summary's
    // columns hold them; only the detail is quoted in the spec's unit.
    std::optional<double> min, max;
    try {
      if (l.min) min = convert(l.term, *l.min, l.unit, row.unit[i], row.units);
      if (l.max) max = convert(l.term, *l.max, l.unit, row.unit[i], row.units);
    } catch (const std::invalid_argument&) {
      unit_errors.push_back(spec.source + ": " + l.key_path + ".unit: '" + l.unit +
                            "' is not a unit of " + name + " for a '" + row.units + "' channel (" +
                            row.device_id + ":" + row.channel +
                            "; accepted: " + join(units::accepted_units(l.term, row.units)) + ")");
      continue;
    }
    const Estimate e{row.value[i], row.sigma[i], row.upper[i], row.detected[i] != 0};
    // A term is never passed or failed from a curve its model does not describe: a poor
    // eq. (3) fit whose model (docs/fit-and-psd.md "When eq. (3) is a poor fit") is still
    // beyond noise leaves every term undecided. Every term, not only those whose taus
    // disagree: the coefficients are fitted together, so a misfit anywhere moves them all.
    const bool beyond_noise = row.fit_within_noise == 0;
    const Outcome o = beyond_noise ? Outcome::Undecided : decide(e, min, max, spec.k);
    v.term_status[i] = outcome_name(o);
    // Which limit the detail quotes: the one failed, else the one straddled, else max.
    const auto [lo, hi] = interval(e, spec.k);
    const bool min_side = !max || (min && (o == Outcome::Fail        ? !(lo > *max)
                                           : o == Outcome::Undecided ? !(hi > *max)
                                                                     : false));
    const char* rel = o == Outcome::Pass   ? (min_side ? ">=" : "<=")
                      : o == Outcome::Fail ? (min_side ? "<" : ">")
                                           : "~";
    terms.emplace_back(o, name + " " + quoted_estimate(l, e, spec.k, row.unit[i], row.units) + " " +
                              rel + " " + number(min_side ? *l.min : *l.max, 4) + " " +
                              units::normalize_spelling(l.unit) +
                              (beyond_noise ? " (fit not within noise)" : ""));
  }
  if (!unit_errors.empty()) throw combined_error(spec.source, std::move(unit_errors));
  Outcome worst = Outcome::Pass;
  for (const auto& [o, text] : terms)
    if (o == Outcome::Fail || (o == Outcome::Undecided && worst == Outcome::Pass)) worst = o;
  v.status = outcome_name(worst);
  for (const auto& [o, text] : terms)
    if (o == worst) v.detail += (v.detail.empty() ? "" : "; ") + text;
  return v;
}

}  // namespace

std::pair<Outcome, std::string> judge_quality(const QualityLimits& q, const io::SummaryRow& row) {
  if (row.quality.empty()) return {Outcome::Undecided, "quality not screened"};
  const std::pair<std::optional<std::int64_t>, std::pair<std::int64_t, const char*>> counts[] = {
      {q.max_gaps, {row.n_gap_runs, "gaps"}},
      {q.max_missing, {row.n_missing, "missing samples"}},
      {q.max_spikes, {row.n_spikes, "spikes"}},
      {q.max_saturated, {row.n_saturated, "saturated samples"}},
      {q.max_stuck, {row.n_stuck, "stuck runs"}},
      {q.max_time_errors, {row.n_time_errors, "time-stamp errors"}},
  };
  std::string detail;
  for (const auto& [limit, count] : counts)
    if (limit && count.first > *limit) {
      detail += detail.empty() ? "quality: " : "; ";
      detail += std::to_string(count.first);
      detail += ' ';
      detail += count.second;
      detail += " > ";
      detail += std::to_string(*limit);
    }
  return {detail.empty() ? Outcome::Pass : Outcome::Fail, detail};
}

Verdict judge(const Spec& spec, const io::SummaryRow& row, const std::string& results_file) {
  const Rule* rule =
      row.status.is_ok() && !row.channel.empty() ? find_rule(spec, row.channel) : nullptr;
  // A rule of masks (and quality) alone needs no fitted value.
  const bool terms = !rule || !rule->limits.empty() || (!rule->quality && rule->masks.empty());
  Verdict v = terms ? judge_terms(spec, row) : Verdict{"pass", "", {}};
  if (rule && !rule->masks.empty()) {
    // The masks' decision joins the terms': fail over undecided (or no data) over pass; on a
    // tie both details are kept.
    const auto [o, detail] = judge_masks(rule->masks, row, results_file);
    const auto rank = [](const std::string& st) { return st == "fail" ? 2 : st == "pass" ? 0 : 1; };
    const std::string st = o == Outcome::Pass ? "pass" : o == Outcome::Fail ? "fail" : "undecided";
    if (rank(st) > rank(v.status)) {
      v.status = st;
      v.detail = detail;
    } else if (st == v.status) {
      v.detail += (v.detail.empty() ? "" : "; ") + detail;
    }
  }
  if (!rule || !rule->quality) return v;
  const auto [o, detail] = judge_quality(*rule->quality, row);
  if (o == Outcome::Fail) {
    // Bad data fail the channel whatever its terms say; the terms that fail too are kept.
    v.detail = v.status == "fail" ? detail + "; " + v.detail : detail;
    v.status = "fail";
  } else if (o == Outcome::Undecided &&
             (v.status == "pass" || (rule->limits.empty() && rule->masks.empty()))) {
    v.status = "undecided";
    v.detail = detail;
  } else if (o == Outcome::Pass && rule->limits.empty() && rule->masks.empty()) {
    return {"pass", "", {}};  // a rule of quality alone needs no fitted value
  }
  return v;
}

std::pair<Outcome, std::string> judge_masks(const std::vector<MaskLimit>& limits,
                                            const io::SummaryRow& row,
                                            const std::string& results_file) {
  Outcome worst = Outcome::Pass;
  std::vector<std::pair<Outcome, std::string>> parts;
  for (const MaskLimit& l : limits) {
    const masks::Mask* m = masks::find_mask(l.mask, l.stat);
    std::pair<Outcome, std::string> part{Outcome::Undecided, ""};
    if (!m) {
      part.second = l.stat + ": no mask " + l.mask;
    } else if (row.units != "s") {
      part.second =
          l.stat + ": " + l.mask + " is a time error in s, the channel is in '" + row.units + "'";
    } else if (results_file.empty()) {
      part.second = l.stat + ": no results file to read the curve from";
    } else {
      try {
        const kernels::StatResult c =
            io::read_stat_group(results_file, row.channel + "/allan/" + l.stat);
        const masks::CurveVerdict cv = masks::judge_curve(*m, c);
        using CO = masks::CurveVerdict::Outcome;
        part = {cv.outcome == CO::Pass   ? Outcome::Pass
                : cv.outcome == CO::Fail ? Outcome::Fail
                                         : Outcome::Undecided,
                cv.detail};
      } catch (const std::exception&) {
        part.second = l.stat + " not computed (analyze --stats " + l.stat + ")";
      }
    }
    if (part.first == Outcome::Fail || (part.first == Outcome::Undecided && worst == Outcome::Pass))
      worst = part.first;
    parts.push_back(std::move(part));
  }
  std::string detail;
  for (const auto& [o, text] : parts)
    if (o == worst) detail += (detail.empty() ? "" : "; ") + text;
  return {worst, detail};
}

namespace {

// "gyro_x (N, B)": a channel's name and the terms with `status`; the input's file name for a
// failed input (no channel).
std::string channel_with_terms(const io::SummaryRow& r, const std::string& status) {
  std::string name = r.channel.empty() ? "input" : r.channel.substr(r.channel.rfind('/') + 1);
  std::string terms;
  for (std::size_t i = 0; i < r.spec_term_status.size(); ++i)
    if (r.spec_term_status[i] == status)
      terms +=
          (terms.empty() ? "" : ", ") + std::string(units::term_name(static_cast<units::Term>(i)));
  return terms.empty() ? name : name + " (" + terms + ")";
}

}  // namespace

void judge_units(std::vector<io::SummaryRow>& rows) {
  std::map<std::string, std::vector<io::SummaryRow*>> units_rows;
  for (io::SummaryRow& r : rows)
    if (!r.spec_status.empty()) units_rows[r.device_id].push_back(&r);
  static constexpr const char* kOrder[] = {"fail", "undecided", "no data"};
  for (auto& entry : units_rows) {
    std::vector<io::SummaryRow*>& members = entry.second;
    std::map<std::string, std::string> by_status;  // status -> "gyro_x (N), accel_y"
    std::size_t covered = 0, passed = 0, no_data = 0;
    for (const io::SummaryRow* r : members) {
      if (r->spec_status == "no spec") continue;
      ++covered;
      passed += r->spec_status == "pass" ? 1 : 0;
      no_data += r->spec_status == "no data" ? 1 : 0;
      if (r->spec_status == "pass") continue;
      std::string& list = by_status[r->spec_status];
      list += (list.empty() ? "" : ", ") + channel_with_terms(*r, r->spec_status);
    }
    std::string status = covered == 0              ? "no spec"
                         : passed == covered       ? "pass"
                         : by_status.count("fail") ? "fail"
                         : no_data == covered      ? "no data"
                                                   : "undecided";
    std::string detail;
    for (const char* s : kOrder)
      if (const auto it = by_status.find(s); it != by_status.end())
        detail += (detail.empty() ? "" : "; ") + std::string(s) + ": " + it->second;
    for (io::SummaryRow* r : members) {
      r->unit_spec_status = status;
      r->unit_spec_detail = detail;
    }
  }
}

}  // namespace allanlot::spec
