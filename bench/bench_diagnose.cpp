// diagnose (kernels/diagnose) on a simulated record shaped like the ADIS16405 z gyroscopes'
// (docs/diagnose.md "Real sensors"): 2000 s at 100 Hz of white and flicker noise, a 20 Hz
// resonance of q 40 whose frequency wanders (spread 0.4 Hz, wander_s 200 s) and a first-order
// 28 Hz filter, diagnosed against white and flicker alone (the resonance and the filter to be
// named), without Monte Carlo replicas (each replica is one simulation and one Allan curve,
// timed by bench_simulate and bench_allan), at 1 and 2 threads. It times the rounds' fits and
// witnesses: the periodogram's line search and the Whittle fits of the resonance's shape.
//
// Run: build/bench/bench_diagnose --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/simulate/simulate.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

namespace {

using namespace allanlot;

constexpr double kRateHz = 100.0;
constexpr std::size_t kSamples = 200'000;

kernels::ChannelSpec given() {
  kernels::ChannelSpec s;
  s.rate_hz = kRateHz;
  s.terms.N = 0.05;
  s.terms.B = 0.01;
  return s;
}

const std::vector<double>& z_gyro_record() {
  static const std::vector<double> y = [] {
    kernels::ChannelSpec truth = given();
    truth.resonances.push_back({0.3, 20.0, 40.0, 0.4, 200.0});
    truth.lowpass.cutoff_hz = 28.0;
    std::vector<double> v(kSamples);
    kernels::simulate_channel(truth, 7, 0, v, 0);
    return v;
  }();
  return y;
}

void BM_DiagnoseZGyro(benchmark::State& state) {
  const std::vector<double>& y = z_gyro_record();
  kernels::DiagnoseOptions opt;
  opt.mc_replicas = 0;
  opt.nthreads = static_cast<int>(state.range(0));
  std::size_t named = 0;
  for (auto _ : state) {
    const kernels::Diagnosis d = kernels::diagnose(y, kRateHz, given(), opt);
    named = d.effects_named.size();
    benchmark::DoNotOptimize(named);
  }
  state.counters["effects_named"] = static_cast<double>(named);
}
BENCHMARK(BM_DiagnoseZGyro)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
