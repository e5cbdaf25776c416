// What a channel's missing samples (NaN) become before its phase is built: the gap policy of
// `analyze --gaps` (docs/statistics.md "Gaps").
//
// A term of an Allan-family estimator that touches a gap is left out (phase.hpp). At a long tau
// every term spans a large share of the record, so a dozen single dropped samples in 10^6 leave
// out most of its terms: the curve loses its longest taus and its intervals widen, and TOTDEV
// and the total family, whose reflections have no meaning across a gap, cannot run at all.
// Filling the short runs by interpolation keeps every term: a filled sample is an estimate of
// the missing one from its neighbours, which changes a term that spans it by a fraction of the
// run's share of the term's window (small at long taus, where filling matters), and the
// intervals count the filled samples as carrying no information (confidence.hpp stat_edf).
#pragma once

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// Longest run of missing samples the default policy fills: the usual logger drop is one to a
/// few rows; a longer run is an outage whose samples interpolation cannot stand in for.
inline constexpr std::int64_t kDefaultMaxFill = 10;

/// The gap policy (docs/cli.md `--gaps`).
struct GapPolicy {
  enum class Mode {
    Skip,  // fill nothing: every term touching a gap is left out ("skip")
    Fill   // fill runs of at most max_run samples; longer runs stay gaps ("fill", "fill:N")
  };
  Mode mode = Mode::Fill;
  std::int64_t max_run = kDefaultMaxFill;  // samples, >= 1; 0 = every run (Mode::Fill only)
  bool operator==(const GapPolicy&) const = default;
};

/// Parses "skip", "fill" (every run) or "fill:N" (runs of at most N >= 1 samples).
/// Throws std::invalid_argument naming the text and the accepted forms.
GapPolicy parse_gap_policy(std::string_view text);
/// The canonical text parse_gap_policy reads back: "skip", "fill" or "fill:N".
std::string to_string(const GapPolicy& policy);

/// What fill_gaps did to one record.
struct GapFill {
  std::int64_t missing = 0;       // missing samples (NaN) in the input
  std::int64_t runs = 0;          // runs of consecutive missing samples in the input
  std::int64_t filled = 0;        // samples filled
  std::int64_t filled_runs = 0;   // runs filled
  std::int64_t runs_left = 0;     // runs left as gaps (longer than the policy fills)
  std::int64_t missing_left = 0;  // their samples
};

/// Fills the runs of NaN in `samples` that `policy` fills, in place, and counts what it did.
/// Interior runs are interpolated linearly between the two valid neighbours: for rate data the
/// missing rate is estimated from the samples beside it, so the phase (its running sum) stays
/// continuous; for phase data the phase itself is interpolated, which is the same as filling
/// its increments with their mean over the run. A run at either end has one neighbour: rate
/// data take its value; phase data continue from it along the record's mean slope (the line
/// through the first and last valid points), so that the phase's trend is kept. Serial, O(N).
/// Preconditions (std::invalid_argument): at least one valid sample when a run is filled.
GapFill fill_gaps(std::span<double> samples, DataType type, const GapPolicy& policy);

/// A row is taken with the terms touching filled samples left out (as `skip` computes it) when
/// that keeps at least this share of the terms the filled record has: at such short taus a
/// filled sample weighs most in the terms spanning it, and leaving out 1 % of the terms changes
/// the estimate by a small part of its interval (the edf falls by at most 1 %). Below the share
/// the filled record's row is taken: leaving out a larger block of terms moves the estimate
/// away from the record's own by up to 2 half-widths on the ADIS16405 units
/// (docs/validation/2026-11-28-gaps.md), more than filling does there.
inline constexpr double kSkipKeepShare = 0.99;

/// fill_gaps then make_phase: the phase of the filled samples, with p.n_filled = the samples
/// filled (the interval rule of confidence.hpp), p.n_gaps = the samples left missing and, when
/// a sample was filled, p.skip_gaps (gaps counting every missing sample of the input).
/// `fill` (optional) receives what fill_gaps did.
PhaseData make_phase(std::span<double> samples, DataType type, double rate_hz,
                     const GapPolicy& policy, GapFill* fill = nullptr, int nthreads = 0);

/// The record as `skip` sees it: p with p.skip_gaps as its gaps and nothing filled (a copy of
/// the phase). Precondition: p.skip_gaps not empty.
PhaseData skip_view(const PhaseData& p);

/// The rows of a statistic on a record with filled samples (kernels::compute): per m, the row
/// of `skipped` (computed on skip_view(p)) when it keeps at least kSkipKeepShare of the terms
/// of the row of `filled` (computed on p), else the row of `filled`; rows in m order. Only m,
/// tau_s, dev and n are read and set (the intervals come after).
StatResult merge_filled_skipped(const StatResult& filled, const StatResult& skipped);

/// A statistic's rows at `ms` (increasing) on `view` = skip_view(p), computed by `run` in
/// batches of 8, 16, 32, ... averaging factors and stopped after the first batch whose last row
/// is not taken against `filled` (the rows on p): the share of terms a gap costs grows with m
/// (each term's span grows), so no later row would be taken, and the rows skip's slower gapped
/// path computes are only those that may be. The batches do not depend on the thread count.
StatResult skipped_rows(
    const PhaseData& view, const std::vector<std::int64_t>& ms, const StatResult& filled,
    const std::function<StatResult(const PhaseData&, const std::vector<std::int64_t>&)>& run);

}  // namespace allanlot::kernels
