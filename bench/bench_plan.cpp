// Cost of `watch`'s look and of `plan`'s search (docs/production.md):
//  - BM_WatchLook: one look at one channel, the fit of what a recording holds (OADEV on 16 taus
//    per decade, its edf, the eq. (3) fit with a new curve shape, as each look's longer record
//    has), by record length at 1 kHz (a MEMS gyro's N, B and K, simulated outside the loop);
//  - BM_PlanLength: plan_length for B to 10 % at 95 % on that gyro.
#include "kernels/plan/length.hpp"
#include "kernels/plan/record_fit.hpp"
#include "kernels/simulate/simulate.hpp"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace allanlot::kernels;

ChannelSpec gyro_x() {
  ChannelSpec s;
  s.rate_hz = 1000.0;
  s.terms.N = 0.0048;
  s.terms.B = 0.00125;
  s.terms.K = 4.6e-7;
  return s;
}

void BM_WatchLook(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<double> y(n);
  simulate_channel(gyro_x(), 1, 0, y, 1);
  for (auto _ : state) {
    Eq3Fit fitter;  // a look's record is longer than the last one's: a new shape each look
    benchmark::DoNotOptimize(fit_record(y, 1000.0, fitter, 1));
  }
  state.SetLabel(std::to_string(n / 1000 / 60) + " min at 1 kHz");
}
BENCHMARK(BM_WatchLook)->Arg(600000)->Arg(1800000)->Arg(5400000)->Unit(benchmark::kMillisecond);

void BM_PlanLength(benchmark::State& state) {
  for (auto _ : state) {
    Eq3Fit fitter;
    benchmark::DoNotOptimize(plan_length(gyro_x(), {Term::B, 0.1, 1.959964}, 100000000, fitter));
  }
}
BENCHMARK(BM_PlanLength)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
