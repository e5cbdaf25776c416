// Allan-family kernels on one 90-minute 1 kHz channel (5.4 M samples, 1 g offset plus 1e-3
// white noise), with the yardsticks they are judged against measured in the same run:
//  - BM_Statistic: each statistic on the default dense grid (log:16, up to the statistic's
//    max_m), at 1 and 2 threads (kernels::compute);
//  - BM_ExtendedStatistic: mtie, tierms, theo1, mtotdev, ttotdev, htotdev and pdev on the octave
//    grid (capped for theo1 and the total family, see extended_m_list) at 1 and 2 threads;
//  - BM_StatisticSimd: oadev, mdev, ohdev and totdev at 1 thread on each SIMD level
//    (baseline SSE2, AVX2, AVX-512; simd:0/1/2), the vectorization step;
//  - BM_TotdevAfterOadev: TOTDEV reusing OADEV's sums (kernels::SumCache), as in `analyze`;
//  - BM_OadevLargeM: the OADEV m above 65536 one sweep per m (swept:0) against the multi-tau
//    sweep (swept:1);
//  - BM_NoiseIdLag1: lag-1 noise identification of every lag-1 m per m (swept:0) against one
//    sweep per differencing level for all m (swept:1);
//  - BM_ConfidenceSixStatistics: the confidence intervals (noise identification, EDF) of the
//    six default statistics of the channel with one shared Lag1Cache, at 1 and 2 threads;
//  - BM_StreamingPass: a plain read pass (sum of squares) over the same phase array, 1 thread:
//    the floor of any statistic that reads every sample once per tau;
//  - BM_Triad: a STREAM-like triad a[i] = b[i] + s c[i] over three 5.4 M-double arrays at 1
//    and 2 OpenMP threads (static schedule): the machine's streaming bound, 24 bytes an
//    element (bytes/s counter, write-allocate traffic not counted);
//  - BM_NaiveOadev, BM_NaiveMdev: the algorithm most tools use, one thread, on the same grid.
//    OADEV: for each m one plain loop over i summing (x[i+2m] - 2 x[i+m] + x[i])^2 in double
//    (one running sum, no tiling). MDEV: AllanTools' method, for each m a freshly allocated
//    double cumulative sum of the phase (as numpy's cumsum) and the squared third differences
//    of its window sums in one running sum. Before timing, each is checked against
//    kernels::compute on the first taus of the grid (relative difference of the deviation at
//    most 1e-9, else the case is skipped with an error; the largest difference is the
//    check_rel_diff counter).
// Every case has a samples/s counter (5.4 M samples per iteration); the statistics and the
// naive baselines also report taus and sample-taus/s. The phase data, the m lists and the
// arrays are built outside the timed loops.
//
// Run: build/bench/bench_allan --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// (bench/run-all runs it with the other programs and writes the ratios to
// bench/results/summary.md; --benchmark_filter=Naive etc. selects cases).
#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/simd.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "kernels/uncertainty/noise_id.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace {

using allanlot::kernels::Stat;

constexpr std::int64_t kSamples = 5'400'000;
constexpr std::size_t kCheckedTaus = 4;  // taus of the grid checked against kernels::compute
constexpr double kCheckTolerance = 1e-9;

const allanlot::kernels::PhaseData& channel() {
  static const allanlot::kernels::PhaseData p = [] {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1e-3);
    std::vector<double> y(static_cast<std::size_t>(kSamples));
    for (auto& v : y)
      v = 9.80665 + g(rng);
    return allanlot::kernels::phase_from_rate(y, 1000.0, 1);
  }();
  return p;
}

std::vector<std::int64_t> default_m_list(Stat stat) {
  const auto& p = channel();
  return allanlot::kernels::make_m_list(allanlot::kernels::TauGridSpec{},
                                        allanlot::kernels::max_m(stat, p.n_points()));
}

void samples_counter(benchmark::State& state) {
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void tau_counters(benchmark::State& state, std::size_t taus) {
  state.counters["taus"] = static_cast<double>(taus);
  // Samples times taus: the work of the overlapping statistics (about N terms per tau).
  state.counters["sample-taus/s"] =
      benchmark::Counter(static_cast<double>(kSamples) * static_cast<double>(taus),
                         benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Statistic(benchmark::State& state) {
  const auto stat = static_cast<Stat>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto& p = channel();
  const auto ms = default_m_list(stat);
  std::size_t rows = 0;
  for (auto _ : state) {
    const auto r = allanlot::kernels::compute(stat, p, ms, threads);
    rows = r.size();
    benchmark::DoNotOptimize(r.dev.data());
  }
  state.SetLabel(std::string(allanlot::kernels::stat_name(stat)) + " " + std::to_string(rows) +
                 " taus");
  samples_counter(state);
  tau_counters(state, rows);
}

// The further statistics on the octave grid (m = 2^k), as Stable32's octave runs: MTIE,
// TIE rms and PDEV (O(N) per tau) up to their largest m; Thêo1 (O(N m/2) per tau) at its even
// octave m 16 .. 256, and the total family (O(N m) per tau, ~18 m operations per window) at
// m = 1 .. 16. Those two costs grow with m, so the full octave grid of a 5.4 M-sample channel
// would take hours: the caps keep one iteration within seconds (docs/performance.md).
std::vector<std::int64_t> extended_m_list(Stat stat) {
  namespace k = allanlot::kernels;
  std::int64_t lo = 1, hi = k::max_m(stat, channel().n_points());
  if (stat == Stat::Theo1) {
    lo = 16;
    hi = 256;
  } else if (stat == Stat::Mtotdev || stat == Stat::Ttotdev || stat == Stat::Htotdev) {
    hi = 16;
  }
  std::vector<std::int64_t> ms;
  for (std::int64_t m = lo; m <= hi; m *= 2)
    ms.push_back(m);
  return ms;
}

void BM_ExtendedStatistic(benchmark::State& state) {
  const auto stat = static_cast<Stat>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto& p = channel();
  const auto ms = extended_m_list(stat);
  std::size_t rows = 0;
  for (auto _ : state) {
    const auto r = allanlot::kernels::compute(stat, p, ms, threads);
    rows = r.size();
    benchmark::DoNotOptimize(r.dev.data());
  }
  state.SetLabel(std::string(allanlot::kernels::stat_name(stat)) + " " + std::to_string(rows) +
                 " octave taus m " + std::to_string(ms.front()) + ".." + std::to_string(ms.back()));
  samples_counter(state);
  tau_counters(state, rows);
}

// The same statistic on each SIMD level (kernels/allan/simd.hpp), 1 thread: the step from the
// baseline SSE2 loops to AVX2 and AVX-512 (same bits on every level). A level this CPU lacks
// is reported as skipped.
void BM_StatisticSimd(benchmark::State& state) {
  namespace k = allanlot::kernels;
  const auto stat = static_cast<Stat>(state.range(0));
  const auto level = static_cast<k::SimdLevel>(state.range(1));
  if (level > k::best_simd_level()) {
    state.SkipWithError("SIMD level not available on this CPU");
    return;
  }
  const k::SimdLevel before = k::simd_level();
  k::set_simd_level(level);
  const auto& p = channel();
  const auto ms = default_m_list(stat);
  std::size_t rows = 0;
  for (auto _ : state) {
    const auto r = k::compute(stat, p, ms, 1);
    rows = r.size();
    benchmark::DoNotOptimize(r.dev.data());
  }
  k::set_simd_level(before);
  state.SetLabel(std::string(k::stat_name(stat)) + " " + std::string(k::simd_level_name(level)));
  samples_counter(state);
  tau_counters(state, rows);
}

// TOTDEV after OADEV on the same channel, as `analyze` runs them: OADEV's sums are TOTDEV's
// inner sums (kernels::SumCache), so TOTDEV only adds its reflected ends. The cache is filled
// by OADEV outside the timed loop; compare with BM_Statistic totdev.
void BM_TotdevAfterOadev(benchmark::State& state) {
  namespace k = allanlot::kernels;
  const auto& p = channel();
  const auto ms = default_m_list(Stat::Totdev);
  k::SumCache cache;
  (void)k::compute(Stat::Oadev, p, default_m_list(Stat::Oadev), 1, &cache);
  std::size_t rows = 0;
  for (auto _ : state) {
    const auto r = k::compute(Stat::Totdev, p, ms, 1, &cache);
    rows = r.size();
    benchmark::DoNotOptimize(r.dev.data());
  }
  samples_counter(state);
  tau_counters(state, rows);
}

// The multi-tau sweep against one sweep per m (the same SIMD block sums, same bits), on the
// OADEV m above 65536 (3 x m > 2^17 phase points): there the shifted streams leave L2 and
// sharing the unshifted one between the m is the sweep's gain. Arg 0: one m at a time
// (detail::second_difference_core per m), arg 1: all together (kernels::compute).
void BM_OadevLargeM(benchmark::State& state) {
  namespace k = allanlot::kernels;
  const auto& p = channel();
  std::vector<std::int64_t> ms;
  for (const std::int64_t m : default_m_list(Stat::Oadev))
    if (m > 65536) ms.push_back(m);
  const bool swept = state.range(0) == 1;
  for (auto _ : state) {
    if (swept) {
      benchmark::DoNotOptimize(k::compute(Stat::Oadev, p, ms, 1).dev.data());
    } else {
      double total = 0.0;
      for (const std::int64_t m : ms)
        total += k::detail::second_difference_core(p, m, 1).sum;
      benchmark::DoNotOptimize(total);
    }
  }
  state.SetLabel(std::string(swept ? "multi-tau sweep, " : "one sweep per m, ") +
                 std::to_string(ms.size()) + " taus");
  samples_counter(state);
  tau_counters(state, ms.size());
}

// Lag-1 noise identification (dmax 3, every default OADEV m with at least 30 averages): one
// m at a time (noise_id_lag1, two passes per level and m) against Lag1Cache::prefetch (two
// sweeps per level for all m together). Same bits (tests/kernels/test_confidence.cpp).
void BM_NoiseIdLag1(benchmark::State& state) {
  namespace k = allanlot::kernels;
  const auto& p = channel();
  std::vector<std::int64_t> ms;
  for (const std::int64_t m : default_m_list(Stat::Oadev))
    if ((p.n_points() - 1) / m >= 30) ms.push_back(m);
  const bool swept = state.range(0) == 1;
  for (auto _ : state) {
    if (swept) {
      k::Lag1Cache cache;
      cache.prefetch(p, ms, 3);
      benchmark::DoNotOptimize(cache.get(p, ms.front(), 3).delta);
    } else {
      int sum = 0;
      for (const std::int64_t m : ms)
        sum += k::noise_id_lag1(p, m, 3).d;
      benchmark::DoNotOptimize(sum);
    }
  }
  state.SetLabel(std::string(swept ? "one sweep per level, " : "per m, ") +
                 std::to_string(ms.size()) + " m");
  samples_counter(state);
}

// Confidence intervals of one channel's six default statistics (noise identification at every
// tau, EDF, chi-square quantiles), with one Lag1Cache per channel as `analyze` keeps it, at 1
// and 2 threads. The deviations are computed outside the timed loop.
void BM_ConfidenceSixStatistics(benchmark::State& state) {
  namespace k = allanlot::kernels;
  const int threads = static_cast<int>(state.range(0));
  const auto& p = channel();
  std::vector<std::pair<Stat, k::StatResult>> rows;
  for (const Stat s : {Stat::Oadev, Stat::Mdev, Stat::Hdev, Stat::Ohdev, Stat::Tdev, Stat::Totdev})
    rows.emplace_back(s, k::compute(s, p, default_m_list(s), threads));
  for (auto _ : state) {
    k::Lag1Cache cache;
    for (auto& [s, r] : rows) {
      k::StatResult copy = r;
      k::add_confidence(s, p, copy, 0.683, threads, &cache);
      benchmark::DoNotOptimize(copy.dev_lo.data());
    }
  }
  samples_counter(state);
}

// Sum of squares over the phase array: one read of 43 MB// Sum of squares over the phase array: one
// read of 43 MB, the floor of any statistic that touches every sample once per tau.
void BM_StreamingPass(benchmark::State& state) {
  const auto& p = channel();
  for (auto _ : state) {
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    const double* x = p.x.data();
    const std::int64_t n = p.n_points() & ~std::int64_t{3};
    for (std::int64_t i = 0; i < n; i += 4) {
      s0 += x[i] * x[i];
      s1 += x[i + 1] * x[i + 1];
      s2 += x[i + 2] * x[i + 2];
      s3 += x[i + 3] * x[i + 3];
    }
    benchmark::DoNotOptimize((s0 + s1) + (s2 + s3));
  }
  samples_counter(state);
}

// STREAM's triad: two 8-byte reads and one 8-byte write per element.
void BM_Triad(benchmark::State& state) {
  [[maybe_unused]] const int threads = static_cast<int>(state.range(0));  // unused without OpenMP
  const std::int64_t n = kSamples;
  std::vector<double> a(static_cast<std::size_t>(n)), b(a.size()), c(a.size());
  double* pa = a.data();
  double* pb = b.data();
  double* pc = c.data();
  // First touch with the timed loop's schedule, as STREAM does.
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    pa[i] = 0.0;
    pb[i] = 1.0;
    pc[i] = 2.0;
  }
  const double s = 3.0;
  for (auto _ : state) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
      pa[i] = pb[i] + s * pc[i];
    benchmark::DoNotOptimize(pa);
    benchmark::ClobberMemory();
  }
  samples_counter(state);
  state.counters["bytes/s"] = benchmark::Counter(24.0 * static_cast<double>(n),
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

// OADEV at one m the way most tools compute it (SP1065 eq. (11)): one loop, one running sum.
double naive_oadev(std::span<const double> x, std::int64_t m, double tau0) {
  const auto n = static_cast<std::int64_t>(x.size());
  double sum = 0.0;
  for (std::int64_t i = 0; i + 2 * m < n; ++i) {
    const double d = x[static_cast<std::size_t>(i + 2 * m)] -
                     2.0 * x[static_cast<std::size_t>(i + m)] + x[static_cast<std::size_t>(i)];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  return std::sqrt(sum / (2.0 * tau * tau * static_cast<double>(n - 2 * m)));
}

// MDEV at one m as AllanTools computes it (SP1065 eq. (14)): a new cumulative sum S of the
// phase for each m, then the window sums' third differences S[j+3m] - 3 S[j+2m] + 3 S[j+m] -
// S[j] squared into one running sum.
double naive_mdev(std::span<const double> x, std::int64_t m, double tau0) {
  const auto n = static_cast<std::int64_t>(x.size());
  const auto cumsum = std::make_unique_for_overwrite<double[]>(x.size() + 1);
  double* s = cumsum.get();
  s[0] = 0.0;
  for (std::int64_t k = 0; k < n; ++k)
    s[k + 1] = s[k] + x[static_cast<std::size_t>(k)];
  double sum = 0.0;
  for (std::int64_t j = 0; j + 3 * m <= n; ++j) {
    const double d = s[j + 3 * m] - 3.0 * s[j + 2 * m] + 3.0 * s[j + m] - s[j];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  const double m2 = static_cast<double>(m) * static_cast<double>(m);
  return std::sqrt(sum / (2.0 * m2 * tau * tau * static_cast<double>(n - 3 * m + 1)));
}

// Largest relative difference between `naive` and kernels::compute on the first taus of `ms`.
template <class Naive>
double naive_rel_diff(Stat stat, const std::vector<std::int64_t>& ms, Naive naive) {
  const auto& p = channel();
  const std::vector<std::int64_t> first(ms.begin(), ms.begin() + std::min(ms.size(), kCheckedTaus));
  const auto r = allanlot::kernels::compute(stat, p, first, 1);
  if (r.size() != first.size()) return INFINITY;
  double worst = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double dev = naive(std::span<const double>(p.x), r.m[i], p.tau0_s);
    worst = std::max(worst, std::abs(dev - r.dev[i]) / std::abs(r.dev[i]));
  }
  return worst;  // NaN compares false below and is reported as a failure
}

template <class Naive>
void run_naive(benchmark::State& state, Stat stat, Naive naive) {
  const auto& p = channel();
  const auto ms = default_m_list(stat);
  const double diff = naive_rel_diff(stat, ms, naive);
  if (!(diff <= kCheckTolerance)) {
    state.SkipWithError(("naive " + std::string(allanlot::kernels::stat_name(stat)) +
                         " differs from kernels::compute by " + std::to_string(diff) +
                         " (relative) on the first taus")
                            .c_str());
    return;
  }
  const std::span<const double> x(p.x);
  for (auto _ : state)
    for (const std::int64_t m : ms)
      benchmark::DoNotOptimize(naive(x, m, p.tau0_s));
  state.SetLabel(std::string(allanlot::kernels::stat_name(stat)) + " " + std::to_string(ms.size()) +
                 " taus, naive");
  state.counters["check_rel_diff"] = diff;
  samples_counter(state);
  tau_counters(state, ms.size());
}

void BM_NaiveOadev(benchmark::State& state) {
  run_naive(state, Stat::Oadev, naive_oadev);
}

void BM_NaiveMdev(benchmark::State& state) {
  run_naive(state, Stat::Mdev, naive_mdev);
}

// The seven statistics of the default dense grid (O(N) per tau); the others are
// BM_ExtendedStatistic's.
void StatArgs(benchmark::internal::Benchmark* b) {
  for (const Stat s :
       {Stat::Adev, Stat::Oadev, Stat::Mdev, Stat::Tdev, Stat::Hdev, Stat::Ohdev, Stat::Totdev})
    for (const int threads : {1, 2})
      b->ArgPair(static_cast<int>(s), threads);
}

void ExtendedArgs(benchmark::internal::Benchmark* b) {
  for (const Stat s : {Stat::Mtie, Stat::Tierms, Stat::Theo1, Stat::Mtotdev, Stat::Ttotdev,
                       Stat::Htotdev, Stat::Pdev})
    for (const int threads : {1, 2})
      b->ArgPair(static_cast<int>(s), threads);
}

BENCHMARK(BM_Statistic)
    ->Apply(StatArgs)
    ->ArgNames({"stat", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ExtendedStatistic)
    ->Apply(ExtendedArgs)
    ->ArgNames({"stat", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
void SimdArgs(benchmark::internal::Benchmark* b) {
  for (const Stat s : {Stat::Oadev, Stat::Mdev, Stat::Ohdev, Stat::Totdev})
    for (const int level : {0, 1, 2})
      b->ArgPair(static_cast<int>(s), level);
}

BENCHMARK(BM_StatisticSimd)
    ->Apply(SimdArgs)
    ->ArgNames({"stat", "simd"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_TotdevAfterOadev)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OadevLargeM)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"swept"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_NoiseIdLag1)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"swept"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ConfidenceSixStatistics)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_StreamingPass)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Triad)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_NaiveOadev)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NaiveMdev)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
