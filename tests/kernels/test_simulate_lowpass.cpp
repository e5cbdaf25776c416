// kernels/simulate's low-pass filter: the filtered simulation's overlapping
// Allan variance is model_avar_sampled's, the factors have their closed forms where there is
// one, a filtered Gauss-Markov effect's is the direct sum's, and the filter is sequential (the
// same bytes for any thread count).
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/simulate/lowpass.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

constexpr double kRate = 100.0;

TEST(SimulateLowpass, FactorsHaveTheirClosedForms) {
  kernels::Lowpass ma2;
  ma2.taps = 2;
  // y' = (y_k + y_{k-1}) / 2: y'_{k+1} - y'_k = (y_{k+1} - y_{k-1}) / 2, variance s^2 / 2 against
  // 2 s^2 unfiltered.
  EXPECT_DOUBLE_EQ(kernels::lowpass_white_fm_factor(ma2, kRate, 1), 0.25);
  // White PM through (1 + z^-1) / 2: sum of (h_k - 2 h_{k-1} + h_{k-2})^2 = 0.25 (1 + 1 + 1 + 1)
  // against 6.
  EXPECT_DOUBLE_EQ(kernels::lowpass_white_pm_factor(ma2, kRate, 1), 1.0 / 6.0);
  // A boxcar of 1.1 samples: h = (1, 0.1) / 1.1, so y'_{k+1} - y'_k has the weights
  // h0, h1 - h0, -h1: factor (h0^2 + (h0 - h1)^2 + h1^2) / 2.
  kernels::Lowpass frac;
  frac.taps = 1.1;
  const double h0 = 1.0 / 1.1, h1 = 0.1 / 1.1;
  EXPECT_NEAR(kernels::lowpass_white_fm_factor(frac, kRate, 1),
              (h0 * h0 + (h0 - h1) * (h0 - h1) + h1 * h1) / 2.0, 1e-15);
  // Far beyond the filter's length the white FM factor is 1 - O(J / m), the white PM one the
  // filter's noise gain sum h^2.
  kernels::Lowpass rc;
  rc.cutoff_hz = 5.0;
  EXPECT_NEAR(kernels::lowpass_white_fm_factor(rc, kRate, 100000), 1.0, 1e-4);
  double h2 = 0.0;
  for (const double v : kernels::lowpass_impulse(rc, kRate))
    h2 += v * v;
  EXPECT_NEAR(kernels::lowpass_white_pm_factor(rc, kRate, 100000), h2, 1e-15);
  EXPECT_DOUBLE_EQ(kernels::lowpass_white_fm_factor(kernels::Lowpass{}, kRate, 3), 1.0);
  EXPECT_NEAR(kernels::lowpass_gain2(rc, kRate, 1e-9), 1.0, 1e-12);
  // The two branches of the white FM factor (m below and above the filter's length) meet.
  const auto j = static_cast<std::int64_t>(kernels::lowpass_impulse(rc, kRate).size());
  EXPECT_NEAR(kernels::lowpass_white_fm_factor(rc, kRate, j - 1),
              kernels::lowpass_white_fm_factor(rc, kRate, j), 2.0 / static_cast<double>(j));
}

// The filtered Gauss-Markov Allan variance against the direct double sum in long double:
// (1/2) sum_k sum_l g_k g_l r(k - l), g the filter convolved with the Allan weights (-1/m on m
// samples, +1/m on the next m) and r the autocovariance of the interval means of the OU process
// (Var = 2 sigma^2 tau_c^2 (a - 1 + e^-a) / h^2, Cov at lag k >= 1 = sigma^2 tau_c^2 (1 - e^-a)^2
// e^-a(k-1) / h^2, a = h / tau_c), a form lowpass_markov_avar does not use.
long double direct_markov_avar(long double sigma, long double tau_c, const kernels::Lowpass& lp,
                               std::int64_t m) {
  const long double h = 1.0L / kRate, a = h / tau_c;
  const long double s2 = sigma * sigma * tau_c * tau_c / (h * h);
  const auto r = [&](std::int64_t k) {
    k = k < 0 ? -k : k;
    if (k == 0) return 2.0L * s2 * (a + std::expm1(-a));
    const long double q = -std::expm1(-a);
    return s2 * q * q * std::exp(-a * static_cast<long double>(k - 1));
  };
  const std::vector<double> imp = kernels::lowpass_impulse(lp, kRate);
  std::vector<long double> g(static_cast<std::size_t>(2 * m) + imp.size() - 1, 0.0L);
  for (std::size_t j = 0; j < imp.size(); ++j)
    for (std::int64_t k = 0; k < 2 * m; ++k)
      g[j + static_cast<std::size_t>(k)] +=
          static_cast<long double>(imp[j]) * (k < m ? -1.0L : 1.0L) / static_cast<long double>(m);
  long double sum = 0.0L;
  for (std::size_t k = 0; k < g.size(); ++k)
    for (std::size_t l = 0; l < g.size(); ++l)
      sum += g[k] * g[l] * r(static_cast<std::int64_t>(k) - static_cast<std::int64_t>(l));
  return sum / 2.0L;
}

TEST(SimulateLowpass, GaussMarkovUnderTheFilterIsTheDirectSum) {
  kernels::Lowpass rc, ma, frac;
  rc.cutoff_hz = 20.0;
  ma.taps = 4.0;
  frac.taps = 1.37;
  for (const kernels::Lowpass& lp : {kernels::Lowpass{}, rc, ma, frac}) {
    const std::vector<double> rho = kernels::lowpass_autocorrelation(lp, kRate);
    for (const double tau_c : {0.003, 0.01, 0.2, 30.0})
      for (const std::int64_t m : {1, 2, 3, 7, 20}) {
        const double got = kernels::lowpass_markov_avar(0.3, tau_c, kRate, m, rho);
        const auto want = static_cast<double>(direct_markov_avar(0.3L, tau_c, lp, m));
        // tau_c = 30 s is 3000 samples: at m = 1 the variance is of order a^3 and the structure
        // function's second difference loses about log10(1 / a) digits of the a^2 it cancels.
        EXPECT_NEAR(got / want, 1.0, tau_c > 1.0 ? 1e-9 : 1e-12)
            << "tau_c " << tau_c << " m " << m << " cutoff " << lp.cutoff_hz << " taps " << lp.taps;
      }
  }
  // Unfiltered it is model_avar's continuous form; with tau_c far below one sample the effect is
  // white noise, and the filter scales it exactly as it scales the white FM term.
  kernels::ChannelSpec gm;
  gm.rate_hz = kRate;
  gm.markovs.push_back({0.3, 0.2});
  EXPECT_NEAR(kernels::lowpass_markov_avar(0.3, 0.2, kRate, 5, {1.0}) /
                  kernels::model_avar(gm, 5.0 / kRate),
              1.0, 1e-12);
  const std::vector<double> rho = kernels::lowpass_autocorrelation(rc, kRate);
  for (const std::int64_t m : {1, 2, 10})
    EXPECT_NEAR(kernels::lowpass_markov_avar(0.3, 1e-5, kRate, m, rho) /
                    kernels::lowpass_markov_avar(0.3, 1e-5, kRate, m, {1.0}),
                kernels::lowpass_white_fm_factor(rc, kRate, m), 1e-3)
        << "m " << m;
}

TEST(SimulateLowpass, FilteredAllanVarianceIsTheModels) {
  constexpr std::size_t n = 20000;
  constexpr int replicas = 12;
  const std::vector<std::int64_t> m{1, 2, 3, 5, 10, 30, 100};
  for (const int form : {0, 1, 2}) {
    kernels::ChannelSpec spec;
    spec.rate_hz = kRate;
    spec.terms.N = 0.01;
    spec.terms.Q = 1e-3;
    spec.sinusoids.push_back({0.02, 20.0, 0.0});
    // A Gauss-Markov effect below one sample (white noise the filter shapes) and one of five.
    spec.markovs.push_back({0.1, 0.004});
    spec.markovs.push_back({0.05, 0.05});
    if (form == 0)
      spec.lowpass.cutoff_hz = 8.0;
    else
      spec.lowpass.taps = form == 1 ? 4.0 : 2.6;
    SCOPED_TRACE(form == 0 ? "first order" : "moving average");
    std::vector<double> mean(m.size(), 0.0);
    kernels::SimulationPlan plan(n);
    std::vector<double> y(n);
    for (int r = 0; r < replicas; ++r) {
      plan.run(spec, 77, static_cast<std::uint64_t>(r), y, 1);
      const auto s =
          kernels::compute(kernels::Stat::Oadev, kernels::phase_from_rate(y, kRate, 1), m, 1);
      for (std::size_t i = 0; i < m.size(); ++i)
        mean[i] += s.dev[i] * s.dev[i] / replicas;
    }
    const auto taps = static_cast<double>(kernels::lowpass_impulse(spec.lowpass, kRate).size());
    for (std::size_t i = 0; i < m.size(); ++i) {
      const double want = kernels::model_avar_sampled(spec, m[i]);
      // About n / (2 m + J + C) independent second differences per replica (J the filter's
      // length, C = 10 samples: twice the longer tau_c), so the mean of the replicas has a
      // relative standard deviation of at most sqrt(2 (2 m + J + C) / (n R)); 5 of them (the
      // sinusoid's fixed phase adds a deterministic end effect of order m / n).
      const double md = static_cast<double>(m[i]);
      const double tol = 5.0 * std::sqrt(2.0 * (2.0 * md + taps + 10.0) / (n * replicas)) + md / n;
      EXPECT_NEAR(mean[i] / want, 1.0, tol) << "m " << m[i];
    }
    // The filter matters where it should: at m = 1 the model is well below the unfiltered one.
    kernels::ChannelSpec raw = spec;
    raw.lowpass = {};
    EXPECT_LT(kernels::model_avar_sampled(spec, 1), 0.8 * kernels::model_avar_sampled(raw, 1));
  }
}

TEST(SimulateLowpass, SameBytesForAnyThreadCountAndBadSpecsRejected) {
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.terms.N = 0.01;
  spec.terms.K = 1e-3;
  spec.lowpass.cutoff_hz = 10.0;
  std::vector<double> a(50000), b(50000);
  kernels::simulate_channel(spec, 5, 1, a, 1);
  kernels::simulate_channel(spec, 5, 1, b, 2);
  EXPECT_EQ(a, b);
  spec.lowpass.taps = 4;  // both forms
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
  spec.lowpass = {};
  spec.lowpass.cutoff_hz = kRate / 2;  // at Nyquist: no filter
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
  spec.lowpass = {};
  spec.lowpass.taps = 1;
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
}

// Rounding after the filter (ChannelSpec::quantum): every sample is a whole number of steps, and
// the Allan variance is the filtered noise's plus the rounding's unfiltered white quantum^2 /
// (12 m), which at m = 1 is what tells it apart from the same white noise under the filter.
TEST(SimulateLowpass, RoundingAfterTheFilterAddsUnfilteredWhiteNoise) {
  constexpr std::size_t n = 50000;
  constexpr int replicas = 12;
  const std::vector<std::int64_t> m{1, 2, 3, 5, 10, 30};
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.terms.N = 0.01;
  spec.lowpass.taps = 1.2;
  spec.offset = 0.3;
  // A step of 0.9 standard deviations of the filtered sample (N sqrt(rate) sqrt(1.04 / 1.44)).
  spec.quantum = 0.9 * spec.terms.N * std::sqrt(kRate * 1.04 / 1.44);
  std::vector<double> mean(m.size(), 0.0);
  kernels::SimulationPlan plan(n);
  std::vector<double> y(n);
  for (int r = 0; r < replicas; ++r) {
    plan.run(spec, 78, static_cast<std::uint64_t>(r), y, 1);
    for (const double v : y)
      ASSERT_NEAR(v / spec.quantum, std::nearbyint(v / spec.quantum), 1e-9);
    const auto s =
        kernels::compute(kernels::Stat::Oadev, kernels::phase_from_rate(y, kRate, 1), m, 1);
    for (std::size_t i = 0; i < m.size(); ++i)
      mean[i] += s.dev[i] * s.dev[i] / replicas;
  }
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double md = static_cast<double>(m[i]);
    const double want = kernels::model_avar_sampled(spec, m[i]);
    const double tol = 5.0 * std::sqrt(2.0 * (2.0 * md + 2.0) / (n * replicas));
    EXPECT_NEAR(mean[i] / want, 1.0, tol) << "m " << m[i];
    kernels::ChannelSpec unrounded = spec;
    unrounded.quantum = 0.0;
    const double rounding = spec.quantum * spec.quantum / (12.0 * md);
    EXPECT_NEAR(want - kernels::model_avar_sampled(unrounded, m[i]), rounding, 1e-12 * want);
  }
  // The same white noise all under the filter is 3.3 % lower at m = 1: more than the 5-sigma
  // tolerance above (1.8 %), so the test tells the two apart.
  kernels::ChannelSpec filtered = spec;
  filtered.quantum = 0.0;
  filtered.terms.N =
      std::sqrt(spec.terms.N * spec.terms.N + spec.quantum * spec.quantum / 12.0 / kRate);
  EXPECT_LT(kernels::model_avar_sampled(filtered, 1), 0.975 * kernels::model_avar_sampled(spec, 1));
}

}  // namespace
}  // namespace allanlot
