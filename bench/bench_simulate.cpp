// Noise synthesis throughput: a six-channel 90-minute IMU unit at 1 kHz (5.4 M samples a
// channel, the paper's recordings) with the demo model's terms (white, flicker, random walk,
// ramp), at 1 and 2 threads. One SimulationPlan is shared by the six channels, as the
// simulate command does, so the flicker filter's spectrum is computed once per plan; the plan
// is made outside the timed loop, the first (spectrum-computing) run included in warm-up.
// Arguments: n (samples a channel) and threads; samples/s counts every channel's samples.
// BM_SimulateEffects times one channel holding every effect outside eq. (3).
// Run: build/bench/bench_simulate --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// (or through bench/run-all).
#include "kernels/simulate/simulate.hpp"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using allanlot::kernels::ChannelSpec;

// The paper's Table in channel units (src/lot/model.cpp's default_demo_model, repeated here
// because the bench links only the kernels): gyros in deg/s, accelerometers in m/s^2.
std::vector<ChannelSpec> demo_unit() {
  const double g = 9.80665e-3;  // m/s^2 per mg
  std::vector<ChannelSpec> u(6);
  u[0].terms = {0, 0.10 / 216000, 4.50 / 3600, 18.00 / 3600, 0};
  u[1].terms = {0, 0, 3.00 / 3600, 4.00 / 3600, 0};
  u[2].terms = {0.02 / 12960000, 0, 0.70 / 3600, 5.80 / 3600, 0};
  u[3].terms = {0.0019 * g / 3600, 0.0071 * g / 60, 0.0175 * g, 0.0295 * g, 0};
  u[4].terms = {0.0026 * g / 3600, 0.001 * g / 60, 0.0160 * g, 0.0410 * g, 0};
  u[5].terms = {0.0009 * g / 3600, 0.0050 * g / 60, 0.0160 * g, 0.0240 * g, 0};
  u[5].offset = 9.80665;
  for (auto& c : u)
    c.rate_hz = 1000;
  return u;
}

void BM_SimulateUnit(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto unit = demo_unit();
  allanlot::kernels::SimulationPlan plan(n);
  std::vector<double> out(n);
  plan.run(unit[0], 1, 0, out, threads);  // computes the filter spectrum
  for (auto _ : state) {
    for (std::size_t c = 0; c < unit.size(); ++c) {
      plan.run(unit[c], 1, c, out, threads);
      benchmark::DoNotOptimize(out.data());
      benchmark::ClobberMemory();
    }
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(n * unit.size()),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

// One channel of state.range(0) samples at state.range(1) threads, white noise of `spec`'s
// level plus what `spec` holds.
void time_one_channel(benchmark::State& state, ChannelSpec spec) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  spec.rate_hz = 1000;
  spec.terms.N = 0.005;
  allanlot::kernels::SimulationPlan plan(n);
  std::vector<double> out(n);
  for (auto _ : state) {
    plan.run(spec, 1, 0, out, threads);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["samples/s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

// White noise alone: the RNG and Box-Muller cost per sample, without the FFT.
void BM_SimulateWhite(benchmark::State& state) {
  time_one_channel(state, ChannelSpec{});
}

// Every effect outside eq. (3) on white noise: two sinusoids, two Gauss-Markov effects (the
// block-parallel carries), two resonances (one wandering: the sequential recursion) and two
// steps, so that the per-effect synthesis loops are timed apart from the flicker FFT.
void BM_SimulateEffects(benchmark::State& state) {
  ChannelSpec spec;
  spec.sinusoids = {{0.01, 13.0, 0.2}, {0.02, 77.0, -1.0}};
  spec.markovs = {{0.01, 0.5}, {0.02, 5.0}};
  spec.resonances = {{0.03, 170.0, 40.0}, {0.02, 210.0, 60.0, 5.0, 3.0}};
  spec.steps = {{0.05, 300.0}, {-0.02, 700.5}};
  time_one_channel(state, spec);
}

}  // namespace

BENCHMARK(BM_SimulateUnit)
    ->ArgPair(5'400'000, 1)
    ->ArgPair(5'400'000, 2)
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_SimulateWhite)
    ->ArgPair(1'000'003, 1)
    ->ArgPair(1'000'003, 2)
    ->ArgPair(5'400'000, 1)
    ->ArgPair(5'400'000, 2)
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(BM_SimulateEffects)
    ->ArgPair(1'000'000, 1)
    ->ArgPair(1'000'000, 2)
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
