// The gap policy's cost (kernels/allan/gaps.hpp) on one 90-minute 1 kHz channel (5.4 M samples,
// 1 g offset plus 1e-3 white noise), one thread:
//  - BM_FillScanGapFree: fill_gaps on the gap-free channel, the only work the policy adds to a
//    channel without gaps (a scan for NaN), against BM_MakePhase, the phase it precedes;
//  - BM_Oadev: OADEV on the default grid (log:16) of the gap-free channel (gapped:0), of the
//    same channel with a dozen drops filled (gapped:1: every row on the filled record, the
//    short taus also on skip's view, each row taken from one of the two) and with the drops
//    left as gaps (gapped:2, `--gaps skip`: every row on the slower gapped path).
// Run: build/bench/bench_gaps --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

namespace {

using namespace allanlot;

constexpr std::int64_t kSamples = 5'400'000;
constexpr double kRateHz = 1000.0;

const std::vector<double>& samples() {
  static const std::vector<double> y = [] {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1e-3);
    std::vector<double> v(kSamples);
    for (double& x : v)
      x = 1.0 + g(rng);
    return v;
  }();
  return y;
}

void BM_FillScanGapFree(benchmark::State& state) {
  std::vector<double> y = samples();
  for (auto _ : state) {
    const kernels::GapFill f = kernels::fill_gaps(y, kernels::DataType::Rate, {});
    benchmark::DoNotOptimize(f);
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void BM_MakePhase(benchmark::State& state) {
  const std::vector<double>& y = samples();
  for (auto _ : state) {
    const kernels::PhaseData p = kernels::make_phase(y, kernels::DataType::Rate, kRateHz, 1);
    benchmark::DoNotOptimize(p.x.data());
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Oadev(benchmark::State& state) {
  std::vector<double> y = samples();
  if (state.range(0) >= 1)
    for (std::int64_t k = 1; k <= 12; ++k)
      y[static_cast<std::size_t>(k * kSamples / 13)] = std::nan("");
  const kernels::GapPolicy policy =
      kernels::parse_gap_policy(state.range(0) == 2 ? "skip" : "fill:10");
  const kernels::PhaseData p = kernels::make_phase(std::span<double>(y), kernels::DataType::Rate,
                                                   kRateHz, policy, nullptr, 1);
  const auto ms = kernels::stat_m_list(
      {}, kernels::Stat::Oadev, kernels::max_m(kernels::Stat::Oadev, p.n_points()), p.n_points());
  for (auto _ : state) {
    const kernels::StatResult r = kernels::compute(kernels::Stat::Oadev, p, ms, 1);
    benchmark::DoNotOptimize(r.dev.data());
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_FillScanGapFree)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MakePhase)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Oadev)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"gapped"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
