// The quality screen (quality.hpp): the run pass and the spike pass, and the decisions taken on
// their tallies (docs/quality.md).
#include "kernels/quality/quality.hpp"

#include "kernels/quality/internal.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace allanlot::kernels {
namespace {

using namespace quality_detail;

void check(const QualityOptions& opt) {
  if (opt.spike_window < 3 || opt.spike_window > 1001 || opt.spike_window % 2 == 0)
    throw std::invalid_argument("screen_quality: spike_window must be odd and in 3..1001, got " +
                                std::to_string(opt.spike_window));
  if (!(opt.spike_sigmas > 0))
    throw std::invalid_argument("screen_quality: spike_sigmas must be > 0, got " +
                                std::to_string(opt.spike_sigmas));
  if (opt.saturation_run < 2)
    throw std::invalid_argument("screen_quality: saturation_run must be >= 2, got " +
                                std::to_string(opt.saturation_run));
  if (!(opt.stuck_expected > 0 && opt.stuck_expected < 1))
    throw std::invalid_argument("screen_quality: stuck_expected must be in (0, 1), got " +
                                std::to_string(opt.stuck_expected));
}

// Stuck output. Model of a clean quantized record: a sample equals its predecessor with
// probability p, and an equality is followed by another with probability q (a first-order
// Markov chain on "equal to the predecessor", which allows the runs of a sensor whose noise is
// below its step to be longer than independent draws would give). A run of length >= L then
// starts at a given sample with probability p q^(L-2), and a record of N samples expects
// N p q^(L-2) of them. The shortest suspicious length L* is the smallest L >= 3 with
// N p q^(L-2) < alpha; by Markov's inequality a clean record shows a run of L* or more with
// probability below alpha (1e-6 by default).
//
// p and q are estimated from the record's own runs, with the runs at least as long as the one
// under suspicion left out (a stuck stretch must not make itself look normal): p = (E + 1) /
// (P + 2) (Laplace's rule, so that a record without a single repeat still has p > 0), q = (E - R
// + p) / (E + 1) (one pseudo-observation of independent draws, under which q = p), where P
// counts consecutive valid pairs, E the equal ones and R the runs of length >= 2. Leaving out
// the runs >= L* can lower L*; the estimate is repeated (at most four times) until L* stops
// falling, so that two stuck stretches do not hide each other.
//
// Real sensors' runs have a heavier tail than one q gives (an output filter makes a run that
// has lasted more likely to last: ADIS16405 accelerometers continue a run of >= 3 more often
// than a run of 2). q is therefore the larger of the above and the same estimate over the runs
// of >= 3 only (continuations past the third sample per run that reached it, with one
// pseudo-observation at q), which keeps the threshold on the safe side of such a tail.
// A run length no record reaches.
constexpr std::int64_t kNever = std::int64_t{1} << 62;

struct StuckModel {
  double p = 0, q = 0;
  std::int64_t min_run = 3;
};

StuckModel stuck_model(const RunHistogram& h, std::int64_t n_pairs, std::int64_t n_valid,
                       std::int64_t cut, double alpha) {
  double equal = 0, runs = 0, excluded_pairs = 0, tail_on = 0, tail_at = 0;
  const auto count = [&](std::int64_t len, const Tally& t) {
    const double c = static_cast<double>(t.count), l = static_cast<double>(len);
    if (len >= cut) {
      excluded_pairs += c * (l - 1);
    } else if (len >= 2) {
      equal += c * (l - 1);
      runs += c;
      if (len >= 3) {
        tail_on += c * (l - 3);
        tail_at += c * (l - 2);
      }
    }
  };
  for (std::int64_t len = 1; len < kShortRuns; ++len)
    count(len, h.shorts[static_cast<std::size_t>(len)]);
  for (const auto& [len, t] : h.longs)
    count(len, t);
  StuckModel m;
  const double pairs = std::max(0.0, static_cast<double>(n_pairs) - excluded_pairs);
  m.p = (equal + 1) / (pairs + 2);
  m.q = (equal - runs + m.p) / (equal + 1);
  m.q = std::max(m.q, (tail_on + m.q) / (tail_at + 1));
  const double expected_starts = static_cast<double>(n_valid) * m.p;
  if (expected_starts < alpha) return m;
  // Smallest k = L - 2 with q^k < alpha / (N p): k > log(alpha / (N p)) / log q.
  const double k = std::floor(std::log(alpha / expected_starts) / std::log(m.q)) + 1;
  m.min_run = k >= 4e18 ? kNever : std::max<std::int64_t>(3, 2 + static_cast<std::int64_t>(k));
  return m;
}

// A run at a saturation value is clipping, already counted as such, not stuck output.
void add_stuck(QualityReport& r, const RunStats& s, std::span<const double> x,
               const std::vector<double>& saturation_values, std::int64_t n_valid, double alpha) {
  const RunHistogram& h = s.valid_runs;
  const auto for_each = [&h](auto f) {
    for (std::int64_t len = 1; len < kShortRuns; ++len)
      f(len, h.shorts[static_cast<std::size_t>(len)]);
    for (const auto& [len, t] : h.longs)
      f(len, t);
  };
  for_each([&r](std::int64_t len, const Tally& t) {
    if (t.count > 0 && len >= r.longest_run &&
        (len > r.longest_run || t.first < r.longest_run_start)) {
      r.longest_run = len;
      r.longest_run_start = t.first;
    }
  });
  if (r.longest_run == 0) return;  // nothing valid
  StuckModel m = stuck_model(h, s.n_pairs, n_valid, r.longest_run, alpha);
  for (int i = 0; i < 4 && m.min_run < r.longest_run; ++i) {
    const StuckModel again = stuck_model(h, s.n_pairs, n_valid, m.min_run, alpha);
    if (again.min_run >= m.min_run) break;
    m = again;
  }
  r.p_equal = m.p;
  r.p_continue = m.q;
  r.stuck_run = m.min_run;
  Tally stuck;
  for_each([&](std::int64_t len, const Tally& t) {
    if (len >= m.min_run) stuck.add(t);
  });
  if (stuck.count > 0 && !saturation_values.empty())
    stuck = long_runs_except(x, m.min_run, saturation_values);
  r.n_stuck_runs = stuck.count;
  r.first_stuck = stuck.first;
}

// Saturation at the storage limits, and at the record's own extremes when they are piled up.
// Returns the values at which runs count as saturation.
std::vector<double> add_saturation(QualityReport& r, const RunStats& s, const QualityInput& in) {
  std::vector<double> values;
  if (in.storage_min) values.push_back(*in.storage_min);
  if (in.storage_max) values.push_back(*in.storage_max);
  Tally sat = s.at_storage_limit;
  std::int64_t samples = s.at_storage_limit_samples;
  // A record spanning only a few quantization steps (a quiet sensor whose noise is below its
  // step) has its extreme among its most frequent values, which is no sign of clipping: the
  // record's own extremes are judged only when it spans at least kMinSpanSteps steps.
  constexpr double kMinSpanSteps = 8;
  const bool resolved =
      s.high[0].set && s.high[0].value - s.low[0].value >= kMinSpanSteps * s.min_step;
  const auto own = [&](const std::array<Extreme, 2>& top, const std::optional<double>& limit) {
    const Extreme& e = top[0];
    if (!e.set || !resolved || e.long_runs.count == 0) return;
    if (limit && e.value == *limit) return;  // counted as a storage limit
    // A natural tail thins out towards the extreme; clipping piles samples up on it.
    const std::int64_t inwards = top[1].set ? top[1].samples : 0;
    if (e.samples <= inwards) return;
    sat.add(e.long_runs);
    samples += e.long_run_samples;
    values.push_back(e.value);
  };
  own(s.high, in.storage_max);
  own(s.low, in.storage_min);
  r.n_saturated_runs = sat.count;
  r.n_saturated_samples = samples;
  r.first_saturated = sat.first;
  return values;
}

}  // namespace

std::string quality_flags(const QualityReport& r) {
  std::string f;
  const auto add = [&f](bool on, const char* name) {
    if (!on) return;
    if (!f.empty()) f += ';';
    f += name;
  };
  add(r.n_gap_runs > 0, "gaps");
  add(r.n_duplicate_times + r.n_decreasing_times > 0, "time_stamps");
  add(r.n_saturated_runs > 0, "saturation");
  add(r.n_stuck_runs > 0, "stuck");
  add(r.n_spikes > 0, "spikes");
  return f;
}

QualityReport screen_quality(const QualityInput& in, const QualityOptions& opt) {
  check(opt);
  QualityReport r;
  r.n_samples = static_cast<std::int64_t>(in.samples.size());
  r.spike_window = opt.spike_window;
  r.n_duplicate_times = in.time.n_duplicate;
  r.first_duplicate_time = in.time.first_duplicate;
  r.n_decreasing_times = in.time.n_decreasing;
  r.first_decreasing_time = in.time.first_decreasing;
  if (in.samples.empty()) return r;

  RunPassOptions ro;
  ro.saturation_run = opt.saturation_run;
  ro.has_min = in.storage_min.has_value();
  ro.has_max = in.storage_max.has_value();
  ro.storage_min = in.storage_min.value_or(0.0);
  ro.storage_max = in.storage_max.value_or(0.0);
  const RunStats s = run_pass(in.samples, ro, opt.threads);
  r.n_missing = s.n_missing;
  r.n_gap_runs = s.gap_runs.count;
  r.first_gap = s.gap_runs.first;
  const std::vector<double> saturation_values = add_saturation(r, s, in);
  add_stuck(r, s, in.samples, saturation_values, r.n_samples - r.n_missing, opt.stuck_expected);

  const SpikeStats sp =
      spike_pass(in.samples, opt.spike_window, opt.spike_sigmas, s.min_step, opt.threads);
  r.n_spikes = sp.spikes.count;
  r.first_spike = sp.spikes.first;
  r.max_spike_sigmas = sp.max_sigmas;
  r.flags = quality_flags(r);
  return r;
}

}  // namespace allanlot::kernels
