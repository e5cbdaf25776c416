// The spec file (`--spec spec.json`): limits on the noise coefficients per channel kind, and the
// pass / fail / undecided decision of each channel of a lot against them (docs/lots-and-slurm.md).
//
//   {
//     "name": "tactical grade",                      (optional, printed with the overview)
//     "confidence": 0.95,                            (optional, default 0.95, in (0, 1))
//     "channels": {
//       "gyro_*":  {"N": {"max": 0.3, "unit": "deg/sqrt(h)"}, "B": {"max": 10, "unit": "deg/h"}},
//       "accel_*": {"N": {"max": 0.06, "unit": "mg/sqrt(Hz)"}, "B": {"min": 0, "max": 0.1,
//                                                                    "unit": "mg"}}
//     }
//   }
//
// Channel keys are fnmatch(3) globs on the channel's path or on its name (as analyze
// --channels); the first key in file order that matches a channel is its rule. Each term (R, K,
// B, N, Q) has "max" and/or "min" (finite, >= 0, min <= max) and a "unit": a datasheet unit of
// the term (kernels/model/units.hpp, primary or secondary form, e.g. N of a gyro in deg/h/sqrt(Hz)
// or deg/sqrt(h)) or the coefficient's unit in the channel's own units (deg/s*s^0.5). Any other
// key, a wrong JSON type, a duplicate key, an impossible value or a malformed channel pattern is
// a spec::Error naming the file and the key path, e.g. "spec.json: channels.gyro_*.N.max: must
// be >= 0, got -1"; every such problem of the file is reported at once, in file order.
//
// A rule may also limit the data-quality screen (docs/quality.md) under the key "quality":
//
//       "gyro_*": {"N": {...}, "quality": {"max_spikes": 0, "saturation": "fail"}}
//
// with "max_gaps" (runs of missing samples), "max_missing" (missing samples), "max_spikes",
// "max_saturated" (samples in saturated runs), "max_stuck" (stuck runs), "max_time_errors"
// (duplicate or decreasing time stamps), each an integer >= 0, and "saturation", "stuck",
// "time_stamps", "gaps", "spikes" as "fail" (the same as its max_ of 0) or "ignore". A channel
// beyond a quality limit fails whatever its terms say.
//
// A rule may hold a channel's MTIE and TDEV to an ITU-T mask (src/lot/masks.hpp), judged per
// tau on the curves of its results file:
//
//       "clock_*": {"mtie": {"mask": "G.811"}, "tdev": {"mask": "G.811"}}
#pragma once

#include "io/results.hpp"
#include "kernels/model/units.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::spec {

/// Problems with a spec file, each "<source>: <key path>: <reason>". parse_spec reports every
/// problem of a file at once: what() is the one message, or "<source>: <n> errors:" followed
/// by one indented line per problem; messages() lists them one by one.
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& what, std::vector<std::string> messages = {})
      : std::runtime_error(what), messages_(std::move(messages)) {
    if (messages_.empty()) messages_.push_back(what);
  }
  const std::vector<std::string>& messages() const { return messages_; }

private:
  std::vector<std::string> messages_;
};

/// The one Error of several problems of the spec `source` (messages non-empty): a single
/// problem as it is, several under the line "<source>: <n> errors:", one indented line each.
Error combined_error(const std::string& source, std::vector<std::string> messages);

/// The limits on one term of one channel rule.
struct TermLimit {
  kernels::units::Term term = kernels::units::Term::N;
  std::optional<double> min, max;  // in `unit`; at least one is set
  std::string unit;                // as written in the file
  std::string key_path;            // e.g. "channels.gyro_*.N", for messages
};

/// Limits on the quality screen's counts (io::SummaryRow's quality columns); unset: no limit.
struct QualityLimits {
  std::optional<std::int64_t> max_gaps, max_missing, max_spikes, max_saturated, max_stuck,
      max_time_errors;
  std::string key_path;  // e.g. "channels.gyro_*.quality", for messages
};

/// A statistic held to an ITU-T mask: "mtie": {"mask": "G.811"}.
struct MaskLimit {
  std::string stat;      // "mtie" or "tdev"
  std::string mask;      // a name of src/lot/masks.hpp
  std::string key_path;  // e.g. "channels.clock_*.mtie", for messages
};

/// The limits for the channels whose path or name matches `glob`.
struct Rule {
  std::string glob;
  std::vector<TermLimit> limits;         // in file order
  std::optional<QualityLimits> quality;  // "quality": {...}
  std::vector<MaskLimit> masks;          // "mtie", "tdev": {"mask": ...}
};

struct Spec {
  std::string source;        // the file name, prefixed to every message
  std::string name;          // "name" of the file, "" when absent
  double confidence = 0.95;  // two-sided level of the intervals the decisions use
  double k = 0;              // the matching normal quantile: 1.95996... at 0.95
  std::vector<Rule> rules;   // in file order: the first match wins
};

/// Parses and validates spec JSON; `source` names it in messages. Throws spec::Error.
Spec parse_spec(std::string_view json_text, const std::string& source);

/// Reads and parses a spec file; one that cannot be read is a spec::Error naming it.
Spec load_spec(const std::filesystem::path& path);

/// k with P(|Z| <= k) = confidence for a standard normal Z, 0 < confidence < 1 (1.959964 at
/// 0.95): the square root of the chi-square(1) quantile, since Z^2 ~ chi-square(1).
double two_sided_normal_quantile(double confidence);

/// The rule of the channel `channel_path` (matched on the path and on its last component),
/// nullptr when none matches.
const Rule* find_rule(const Spec& spec, const std::string& channel_path);

/// `value` of term `t` given in `from_unit` expressed in `to_unit`, both accepted units of the
/// term for a channel in `channel_units` (kernels::units::accepted_units), converted through
/// the audited units module. Throws std::invalid_argument naming the unit that does not fit.
double convert(kernels::units::Term t, double value, std::string_view from_unit,
               std::string_view to_unit, std::string_view channel_units);

enum class Outcome { Pass, Fail, Undecided };

/// A fitted coefficient in the unit of the limits it is compared with.
struct Estimate {
  double value = 0;  // the fitted value
  double sigma = 0;  // its 1-sigma uncertainty
  double upper = 0;  // one-sided 95 % upper bound (used when not detected; NaN = none)
  bool detected = false;
};

/// The interval [lo, hi] of an estimate at the quantile k: value -+ k sigma for a detected
/// term (lo clipped at 0: coefficients are >= 0); for an undetected one [0, upper] (the fit's
/// own bound, since the value then is consistent with zero and a symmetric interval would
/// misstate it), or [0, value + k sigma] when the bound is missing. A non-finite sigma makes
/// the interval [0, inf).
std::pair<double, double> interval(const Estimate& e, double k);

/// The decision of one term: against max, pass when hi <= max, fail when lo > max; against
/// min, pass when lo >= min, fail when hi < min; undecided otherwise (the interval straddles
/// the limit). With both limits, a fail on either fails, else an undecided on either.
Outcome decide(const Estimate& e, std::optional<double> min, std::optional<double> max, double k);

/// The decision of a row's quality counts against `q`: fail when a count exceeds its limit,
/// undecided when the row was not screened (its `quality` is empty: an older results file),
/// pass otherwise; the detail names the counts beyond their limits, e.g. "quality: 3 spikes >
/// 0", or "quality not screened".
std::pair<Outcome, std::string> judge_quality(const QualityLimits& q, const io::SummaryRow& row);

/// The spec_status and spec_detail of one summary row (io::SummaryRow): "no data" for a failed
/// row or one without any fitted value, "no spec" when no rule matches the channel, otherwise
/// fail if a term fails, else undecided if a term is undecided (a limited term without an
/// estimate is undecided), else pass. A rule's quality limits come on top: a quality failure
/// fails the row (also one without a fitted value), an unscreened row that would pass is
/// undecided, and a rule of quality limits alone passes a screened row within them. The detail
/// lists the terms behind the status, e.g. "N 18.3±0.04 > 18 deg/h/sqrt(Hz)" (± is k sigma) or "B
/// <12 ~ 10 deg/h" (undetected: the upper bound). Throws spec::Error when a matching rule's unit
/// does not fit the channel, naming every such limit of the rule (Error::messages, one each).
struct Verdict {
  std::string status;
  std::string detail;
  std::array<std::string, 5> term_status;  // per term R..Q: "pass", "fail", "undecided" or ""
};
/// A rule's masks (judge_masks) are judged on the curves of `results_file`, the row's results
/// file ("" = none: a mask is then undecided).
Verdict judge(const Spec& spec, const io::SummaryRow& row, const std::string& results_file = "");

/// The decision of a row's MTIE and TDEV against the rule's masks (masks::judge_curve per
/// tau), the curves read from `results_file`: fail when a curve fails, else undecided when
/// one straddles its mask, has no tau inside it, was not computed, or the channel is not in
/// seconds (masks are time errors in s), else pass; the detail names each mask's decision.
std::pair<Outcome, std::string> judge_masks(const std::vector<MaskLimit>& masks,
                                            const io::SummaryRow& row,
                                            const std::string& results_file);

/// The per-unit verdict, from the rows' spec_status (judge() first): for each device_id, the
/// unit fails when any of its channels fails; otherwise it is undecided when any channel is
/// undecided or has no data (a failed channel or input cannot be said to pass); it passes only
/// when every channel a rule covers passes. Channels without a rule ("no spec") do not count; a
/// unit with none covered is "no spec", one whose covered channels all have no data "no data".
/// Sets unit_spec_status and unit_spec_detail (the channels behind the verdict, by status, with
/// the terms that decided each, e.g. "fail: gyro_x (N, B); undecided: accel_z") on every row of
/// the unit; rows without a spec_status (no spec given) are left alone.
void judge_units(std::vector<io::SummaryRow>& rows);

}  // namespace allanlot::spec
