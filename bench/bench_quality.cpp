// The data-quality screen (kernels/quality) on one 90-minute 1 kHz channel (5.4 M samples), with
// its yardstick measured in the same run (docs/performance.md):
//  - BM_QualityScreen: screen_quality at 1 and 2 threads on two channels: float (1 g offset
//    plus 1e-3 white noise, bench_allan.cpp's) and quantized (a gyro's white noise of 8 steps
//    of 0.02 deg/s plus a random walk, rounded to the step as an int16 ADC delivers it, with
//    the storage limits given);
//  - BM_OadevSameChannel: oadev on the default dense grid (log:16) of the float channel at 1 and
//    2 threads, from the phase built outside the timed loop (as BM_Statistic of bench_allan).
// Both have a samples/s counter.
//
// Run: build/bench/bench_quality --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/quality/quality.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

constexpr std::int64_t kSamples = 5'400'000;
constexpr double kStep = 0.02;

const std::vector<double>& float_channel() {
  static const std::vector<double> y = [] {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1e-3);
    std::vector<double> v(static_cast<std::size_t>(kSamples));
    for (auto& x : v)
      x = 9.80665 + g(rng);
    return v;
  }();
  return y;
}

const std::vector<double>& quantized_channel() {
  static const std::vector<double> y = [] {
    std::mt19937_64 rng(2);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> v(static_cast<std::size_t>(kSamples));
    double walk = 0;
    for (auto& x : v) {
      walk += 1e-3 * g(rng);
      x = std::round(8.0 * g(rng) + walk) * kStep;
    }
    return v;
  }();
  return y;
}

void samples_counter(benchmark::State& state) {
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void BM_QualityScreen(benchmark::State& state) {
  const bool quantized = state.range(0) != 0;
  allanlot::kernels::QualityInput in;
  in.samples = quantized ? quantized_channel() : float_channel();
  if (quantized) {
    in.storage_min = -32768 * kStep;
    in.storage_max = 32767 * kStep;
  }
  allanlot::kernels::QualityOptions opt;
  opt.threads = static_cast<int>(state.range(1));
  std::int64_t flagged = 0;
  for (auto _ : state) {
    const auto r = allanlot::kernels::screen_quality(in, opt);
    flagged = r.flags.empty() ? 0 : 1;
    benchmark::DoNotOptimize(r.n_spikes);
  }
  state.SetLabel(quantized ? "quantized" : "float");
  state.counters["flagged"] = static_cast<double>(flagged);
  samples_counter(state);
}

void BM_OadevSameChannel(benchmark::State& state) {
  static const allanlot::kernels::PhaseData p =
      allanlot::kernels::phase_from_rate(float_channel(), 1000.0, 1);
  const auto ms = allanlot::kernels::make_m_list(
      allanlot::kernels::TauGridSpec{},
      allanlot::kernels::max_m(allanlot::kernels::Stat::Oadev, p.n_points()));
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const auto r = allanlot::kernels::compute(allanlot::kernels::Stat::Oadev, p, ms, threads);
    benchmark::DoNotOptimize(r.dev.data());
  }
  samples_counter(state);
}

BENCHMARK(BM_QualityScreen)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->ArgNames({"quantized", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OadevSameChannel)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
