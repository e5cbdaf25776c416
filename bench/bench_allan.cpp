// Allan-family kernels on one 90-minute 1 kHz channel (5.4 M samples, 1 g offset plus 1e-3
// white noise): each statistic on the default dense grid (log:16, up to the statistic's
// max_m), at 1 and 2 threads, and a plain streaming pass over the same phase array as the
// memory-bandwidth yardstick. The phase data and m lists are built outside the timed loop.
// Run: bench_allan --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "kernels/phase.hpp"
#include "kernels/stats.hpp"
#include "kernels/tau_grid.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

namespace {

using allanlot::kernels::Stat;

constexpr std::int64_t kSamples = 5'400'000;

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

void BM_Statistic(benchmark::State& state) {
  const auto stat = static_cast<Stat>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto& p = channel();
  const auto ms = allanlot::kernels::make_m_list(allanlot::kernels::TauGridSpec{},
                                                 allanlot::kernels::max_m(stat, p.n_points()));
  std::size_t rows = 0;
  for (auto _ : state) {
    const auto r = allanlot::kernels::compute(stat, p, ms, threads);
    rows = r.size();
    benchmark::DoNotOptimize(r.dev.data());
  }
  state.SetLabel(std::string(allanlot::kernels::stat_name(stat)) + " " + std::to_string(rows) +
                 " taus");
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
  // Samples times taus: the work of the overlapping statistics (about N terms per tau).
  state.counters["sample-taus/s"] =
      benchmark::Counter(static_cast<double>(kSamples) * static_cast<double>(rows),
                         benchmark::Counter::kIsIterationInvariantRate);
}

// Sum of squares over the phase array: one read of 43 MB, the floor of any statistic that
// touches every sample once per tau.
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
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void StatArgs(benchmark::internal::Benchmark* b) {
  for (const Stat s : allanlot::kernels::all_stats())
    for (const int threads : {1, 2})
      b->ArgPair(static_cast<int>(s), threads);
}

BENCHMARK(BM_Statistic)
    ->Apply(StatArgs)
    ->ArgNames({"stat", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_StreamingPass)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
