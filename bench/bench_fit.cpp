// Cost of the eq. (3) fit on analyze's default curve (docs/statistics.md "Tau grids"): one
// 5.4 M-sample channel (90 min at 1 kHz) with 16 taus per decade up to m = N/4 (about 100 taus).
//  - BM_FitFirstChannel: a fresh plan per iteration, so each fit also builds the covariance
//    basis (what the first channel of a shape pays);
//  - BM_FitNextChannel: the plan reused (what every further channel of the lot pays): the
//    reweighted NNLS, the covariance assembly, the sandwich, chi2 and the read-outs;
//  - BM_CovarianceBasis: the basis alone, by number of taus per decade.
// The curve is the paper's gyro X model with a deterministic ripple, so that the fit iterates
// as on data; simulating and computing the OADEV are outside the timed loop (bench_allan).
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace allanlot::kernels;

struct Curve {
  std::vector<double> tau, avar, edf;
  std::vector<std::int64_t> m, n;
  double tau0 = 1e-3;
  std::int64_t n_samples = 5400000;
  FitInput input() const {
    FitInput in;
    in.tau_s = tau;
    in.values = avar;
    in.n = n;
    in.edf = edf;
    in.tau0_s = tau0;
    in.n_samples = n_samples;
    return in;
  }
};

Curve paper_curve(int per_decade) {
  Curve c;
  const std::array<double, kNumTerms> theta = {0.0, 4.63e-7 * 4.63e-7, 0.00125 * 0.00125,
                                               0.005 * 0.005, 0.0};
  c.m = make_m_list(parse_tau_grid("log:" + std::to_string(per_decade)),
                    max_m(Stat::Oadev, c.n_samples + 1));
  for (std::size_t i = 0; i < c.m.size(); ++i) {
    const double tau = static_cast<double>(c.m[i]) * c.tau0;
    c.tau.push_back(tau);
    c.avar.push_back(eq3_avar(theta, tau) * (1.0 + 0.02 * std::sin(1.3 * static_cast<double>(i))));
    c.n.push_back(c.n_samples + 1 - 2 * c.m[i]);
    c.edf.push_back(edf_greenhall(0, {2, true, false}, c.m[i], c.n_samples + 1));
  }
  return c;
}

void BM_FitFirstChannel(benchmark::State& state) {
  const Curve c = paper_curve(16);
  for (auto _ : state) {
    Eq3Fit fit(c.tau.size());
    benchmark::DoNotOptimize(fit.fit(c.input()));
  }
  state.counters["taus"] = static_cast<double>(c.tau.size());
  state.counters["channels/s"] =
      benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FitFirstChannel)->Unit(benchmark::kMillisecond);

void BM_FitNextChannel(benchmark::State& state) {
  const Curve c = paper_curve(16);
  Eq3Fit fit(c.tau.size());
  benchmark::DoNotOptimize(fit.fit(c.input()));  // builds the basis outside the loop
  for (auto _ : state)
    benchmark::DoNotOptimize(fit.fit(c.input()));
  state.counters["taus"] = static_cast<double>(c.tau.size());
  state.counters["channels/s"] =
      benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FitNextChannel)->Unit(benchmark::kMicrosecond);

void BM_CovarianceBasis(benchmark::State& state) {
  const Curve c = paper_curve(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    OavarCovariance cov;
    cov.prepare(c.m, c.n, c.tau0);
    benchmark::DoNotOptimize(cov.size());
  }
  state.counters["taus"] = static_cast<double>(c.tau.size());
  state.counters["pairs/s"] =
      benchmark::Counter(static_cast<double>(c.tau.size() * (c.tau.size() + 1) / 2),
                         benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_CovarianceBasis)->Arg(5)->Arg(10)->Arg(16)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
