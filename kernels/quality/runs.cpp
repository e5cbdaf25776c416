// The run pass of the quality screen: one walk over the maximal runs of equal samples (and of
// missing ones), giving the gaps, the run-length histogram the stuck test needs, the runs at the
// storage limits, the record's two largest and two smallest values with their runs, and the
// quantization step.
//
// Chunking: a chunk owns the runs that start in it and follows its last run past its end, so a
// run is seen whole by exactly one chunk and no merge has to stitch runs together.
#include "kernels/common/parallel.hpp"
#include "kernels/quality/internal.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace allanlot::kernels::quality_detail {
namespace {

bool same(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

// Adds a run (or a merged Extreme) of `value` to the top two distinct values under `before`
// (std::greater for the largest, std::less for the smallest).
template <class Before>
void absorb(std::array<Extreme, 2>& top, const Extreme& e, Before before) {
  if (!e.set) return;
  const auto accumulate = [&e](Extreme& t) {
    t.samples += e.samples;
    t.long_runs.add(e.long_runs);
    t.long_run_samples += e.long_run_samples;
  };
  if (!top[0].set || before(e.value, top[0].value)) {
    top[1] = top[0];
    top[0] = e;
  } else if (e.value == top[0].value) {
    accumulate(top[0]);
  } else if (!top[1].set || before(e.value, top[1].value)) {
    top[1] = e;
  } else if (e.value == top[1].value) {
    accumulate(top[1]);
  }
}

void add_valid_run(RunStats& s, std::span<const double> x, std::int64_t start, std::int64_t end,
                   const RunPassOptions& opt) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  const std::int64_t len = end - start;
  const double v = x[static_cast<std::size_t>(start)];
  s.valid_runs.add(len, start);
  s.n_pairs += len - 1;
  if (end < n) {
    const double next = x[static_cast<std::size_t>(end)];
    if (!std::isnan(next)) {
      ++s.n_pairs;
      s.min_step = std::min(s.min_step, std::abs(next - v));
    }
  }
  const bool long_run = len >= opt.saturation_run;
  if (long_run &&
      ((opt.has_min && v == opt.storage_min) || (opt.has_max && v == opt.storage_max))) {
    s.at_storage_limit.add(1, start);
    s.at_storage_limit_samples += len;
  }
  Extreme e;
  e.set = true;
  e.value = v;
  e.samples = len;
  if (long_run) {
    e.long_runs.add(1, start);
    e.long_run_samples = len;
  }
  // Most values are neither among the two largest nor the two smallest so far: skip them cheaply.
  if (!s.high[1].set || v >= s.high[1].value) absorb(s.high, e, std::greater<double>());
  if (!s.low[1].set || v <= s.low[1].value) absorb(s.low, e, std::less<double>());
}

RunStats chunk_pass(std::span<const double> x, std::int64_t begin, std::int64_t end,
                    const RunPassOptions& opt) {
  RunStats s;
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  const auto at = [&x](std::int64_t i) { return x[static_cast<std::size_t>(i)]; };
  std::int64_t i = begin;
  while (i > 0 && i < end && same(at(i), at(i - 1)))  // the run that started earlier is not ours
    ++i;
  while (i < end) {
    std::int64_t j = i + 1;
    while (j < n && same(at(j), at(i)))
      ++j;
    if (std::isnan(at(i))) {
      s.n_missing += j - i;
      s.gap_runs.add(1, i);
    } else {
      add_valid_run(s, x, i, j, opt);
    }
    i = j;
  }
  return s;
}

}  // namespace

void RunStats::merge(const RunStats& later) {
  n_missing += later.n_missing;
  gap_runs.add(later.gap_runs);
  n_pairs += later.n_pairs;
  valid_runs.add(later.valid_runs);
  at_storage_limit.add(later.at_storage_limit);
  at_storage_limit_samples += later.at_storage_limit_samples;
  for (const Extreme& e : later.high)
    absorb(high, e, std::greater<double>());
  for (const Extreme& e : later.low)
    absorb(low, e, std::less<double>());
  min_step = std::min(min_step, later.min_step);
}

Tally long_runs_except(std::span<const double> x, std::int64_t min_length,
                       std::span<const double> except) {
  Tally t;
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  const auto at = [&x](std::int64_t i) { return x[static_cast<std::size_t>(i)]; };
  for (std::int64_t i = 0; i < n;) {
    std::int64_t j = i + 1;
    while (j < n && same(at(j), at(i)))
      ++j;
    const double v = at(i);
    if (!std::isnan(v) && j - i >= min_length &&
        std::find(except.begin(), except.end(), v) == except.end())
      t.add(1, i);
    i = j;
  }
  return t;
}

RunStats run_pass(std::span<const double> x, const RunPassOptions& opt, int threads) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  // The chunk count is fixed by the thread count only; any count gives the same result because
  // every merge is exact (internal.hpp).
  const int nt = std::max(1, std::min<int>(resolve_threads(threads), static_cast<int>(n / 65536)));
  std::vector<RunStats> parts(static_cast<std::size_t>(nt));
  ExceptionCollector errors;
#pragma omp parallel for num_threads(nt) schedule(static, 1)
  for (int c = 0; c < nt; ++c)
    errors.run([&] {
      const std::int64_t b = n * c / nt, e = n * (c + 1) / nt;
      parts[static_cast<std::size_t>(c)] = chunk_pass(x, b, e, opt);
    });
  errors.rethrow();
  RunStats all = std::move(parts.front());
  for (std::size_t c = 1; c < parts.size(); ++c)
    all.merge(parts[c]);
  return all;
}

}  // namespace allanlot::kernels::quality_detail
