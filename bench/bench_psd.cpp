// Cost of the PSD side of a channel: one 5.4 M-sample channel (90 min at 1 kHz, the paper's
// gyro X), at 1 and 2 threads (the benchmark argument):
//  - BM_Welch: the Welch PSD (Hann, 50 % overlap, L = 2^18 by the segment rule: 40 segments);
//  - BM_Eq2: equation (2) on that PSD at the default OADEV taus (log:16, about 90);
//  - BM_PsdFit: the PSD-domain eq. (3) fit (no threads inside) of a first channel, and
//    BM_PsdFitNextChannel of the next ones (regressors from the WelchTermCache);
//  - BM_PsdCrosscheck: the three together plus the log binning, i.e. what `analyze` adds to a
//    channel for psd/, psd_fit/ and crosscheck/.
// Simulation is outside the timed loops. Every case reports samples/s: the channel's 5.4 M
// samples per iteration (for BM_Eq2 and BM_PsdFit, whose input is the PSD, the rate at which
// channels of that length are served). The thread count is the "threads" argument.
// Run: build/bench/bench_psd --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// (or through bench/run-all).
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/model/psd_fit.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/spectral/psd.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

namespace {

using namespace allanlot::kernels;

constexpr std::size_t kSamples = 5400000;
constexpr double kRate = 1000.0;

const std::vector<double>& channel() {
  static const std::vector<double> y = [] {
    ChannelSpec s;
    s.rate_hz = kRate;
    s.terms.N = 0.005;
    s.terms.B = 0.00125;
    s.terms.K = 4.63e-7;
    std::vector<double> v(kSamples);
    simulate_channel(s, 1, 0, v, 0);
    return v;
  }();
  return y;
}

std::vector<double> default_taus() {
  const auto n_points = static_cast<std::int64_t>(kSamples) + 1;
  const auto m = make_m_list(parse_tau_grid("log:16"), max_m(Stat::Oadev, n_points), n_points);
  std::vector<double> taus;
  for (const auto mi : m)
    taus.push_back(static_cast<double>(mi) / kRate);
  return taus;
}

void samples_counter(benchmark::State& state) {
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Welch(benchmark::State& state) {
  const auto& y = channel();
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state)
    benchmark::DoNotOptimize(welch_psd(y, kRate, threads));
  samples_counter(state);
}
BENCHMARK(BM_Welch)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Eq2(benchmark::State& state) {
  const PsdResult p = welch_psd(channel(), kRate, 0);
  const auto taus = default_taus();
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state)
    benchmark::DoNotOptimize(avar_from_psd(p, taus, {}, threads));
  state.counters["taus"] = static_cast<double>(taus.size());
  samples_counter(state);
}
BENCHMARK(BM_Eq2)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The first channel of a segment length computes the terms' expected Welch spectra; the next
// ones take them from the WelchTermCache, as `analyze` does (BM_PsdFitNextChannel).
void BM_PsdFit(benchmark::State& state) {
  const PsdResult p = welch_psd(channel(), kRate, 0);
  for (auto _ : state)
    benchmark::DoNotOptimize(psd_fit(p));
  samples_counter(state);
}
BENCHMARK(BM_PsdFit)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PsdFitNextChannel(benchmark::State& state) {
  const PsdResult p = welch_psd(channel(), kRate, 0);
  WelchTermCache terms;
  (void)psd_fit(p, {}, &terms);
  for (auto _ : state)
    benchmark::DoNotOptimize(psd_fit(p, {}, &terms));
  samples_counter(state);
}
BENCHMARK(BM_PsdFitNextChannel)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PsdCrosscheck(benchmark::State& state) {
  const auto& y = channel();
  const auto taus = default_taus();
  const int threads = static_cast<int>(state.range(0));
  WelchTermCache terms;  // as in `analyze`: a lot's channels share the regressors
  (void)psd_fit(welch_psd(y, kRate, threads), {}, &terms);
  for (auto _ : state) {
    const PsdResult p = welch_psd(y, kRate, threads);
    benchmark::DoNotOptimize(log_bin(p));
    benchmark::DoNotOptimize(avar_from_psd(p, taus, {}, threads));
    benchmark::DoNotOptimize(psd_fit(p, {}, &terms));
  }
  samples_counter(state);
}
BENCHMARK(BM_PsdCrosscheck)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
