// kernels/simulate's resonance: its closed-form autocovariance is the AR(2)
// recursion's, its Allan variance (plain and under the sensor's filter) the direct sum's in
// long double, its PSD the autocovariance's Fourier series, and the simulated process has the
// model's autocovariance and Allan variance within what its degrees of freedom allow.
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/simulate/resonance.hpp"
#include "kernels/simulate/rng.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/spectral/psd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

constexpr double kRate = 100.0;

// The autocovariance by the Yule-Walker start and the recursion, in long double: C(0) = sigma^2,
// C(1) = a1 C(0) / (1 - a2), C(k) = a1 C(k-1) + a2 C(k-2) (a form resonance_autocovariance does
// not use).
std::vector<long double> recursion_autocovariance(const kernels::Resonance& r, std::size_t n) {
  const long double theta = 2.0L * std::numbers::pi_v<long double> * r.frequency_hz / kRate;
  const long double rr = std::exp(-0.5L * theta / r.q);
  const long double a1 = 2.0L * rr * std::cos(theta), a2 = -rr * rr;
  std::vector<long double> c(n);
  c[0] = static_cast<long double>(r.sigma) * r.sigma;
  if (n > 1) c[1] = a1 * c[0] / (1.0L - a2);
  for (std::size_t k = 2; k < n; ++k)
    c[k] = a1 * c[k - 1] + a2 * c[k - 2];
  return c;
}

// The overlapping Allan variance of a stationary sequence with autocovariance c, filtered by h:
// the filtered autocovariance c_f(k) = sum_ij h_i h_j c(k + i - j), then
// avar(m) = (1 / m^2) sum_{|j| < m} (m - |j|) (c_f(j) - c_f(m + j)).
long double direct_avar(const std::vector<long double>& c, const std::vector<double>& h,
                        std::int64_t m) {
  const auto cf = [&](std::int64_t k) {
    long double s = 0.0L;
    for (std::size_t i = 0; i < h.size(); ++i)
      for (std::size_t j = 0; j < h.size(); ++j) {
        std::int64_t lag = k + static_cast<std::int64_t>(i) - static_cast<std::int64_t>(j);
        lag = lag < 0 ? -lag : lag;
        s += static_cast<long double>(h[i]) * h[j] * c[static_cast<std::size_t>(lag)];
      }
    return s;
  };
  long double s = 0.0L;
  for (std::int64_t j = -(m - 1); j < m; ++j)
    s += static_cast<long double>(m - (j < 0 ? -j : j)) * (cf(j) - cf(m + j));
  return s / (static_cast<long double>(m) * m);
}

TEST(SimulateResonance, AutocovarianceIsTheRecursions) {
  for (const double f0 : {20.0, 1.0, 0.1})
    for (const double q : {0.5, 3.0, 100.0}) {
      const kernels::Resonance r{0.25, f0, q};
      const auto want = recursion_autocovariance(r, 400);
      const auto got = kernels::resonance_autocovariance(r, kRate, 400);
      for (std::size_t k = 0; k < want.size(); ++k)
        EXPECT_NEAR(got[k], static_cast<double>(want[k]), 1e-12 * 0.0625)
            << "f0 " << f0 << " q " << q << " k " << k;
    }
}

TEST(SimulateResonance, AllanVarianceIsTheDirectSum) {
  kernels::Lowpass rc, ma;
  rc.cutoff_hz = 25.0;
  ma.taps = 1.6;
  for (const kernels::Lowpass& lp : {kernels::Lowpass{}, rc, ma}) {
    const std::vector<double> rho = kernels::lowpass_autocorrelation(lp, kRate);
    const std::vector<double> h = kernels::lowpass_impulse(lp, kRate);
    for (const double f0 : {20.0, 1.0, 0.1})
      for (const double q : {0.5, 3.0, 100.0}) {
        const kernels::Resonance r{0.25, f0, q};
        const auto c = recursion_autocovariance(r, 2 * 300 + h.size() + 2);
        for (const std::int64_t m : {1, 2, 3, 4, 7, 20, 150, 300}) {
          const double got = kernels::resonance_avar(r, kRate, static_cast<double>(m), rho);
          const auto want = static_cast<double>(direct_avar(c, h, m));
          // f0 = 0.1 Hz is 1000 samples a period: at m = 1 the variance is of order (m/1000)^2
          // sigma^2 and the structure function's second difference loses the digits it cancels.
          EXPECT_NEAR(got / want, 1.0, f0 < 0.5 ? 1e-8 : 1e-11)
              << "f0 " << f0 << " q " << q << " m " << m << " cutoff " << lp.cutoff_hz;
        }
      }
  }
  // model_avar_sampled takes it, filtered and not, and model_avar interpolates between samples.
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.resonances.push_back({0.25, 20.0, 50.0});
  spec.lowpass = rc;
  EXPECT_NEAR(kernels::model_avar_sampled(spec, 3) /
                  kernels::resonance_avar(spec.resonances[0], kRate, 3.0,
                                          kernels::lowpass_autocorrelation(rc, kRate)),
              1.0, 1e-12);
  const double a3 = kernels::model_avar(spec, 0.03), a4 = kernels::model_avar(spec, 0.04);
  const double a35 = kernels::model_avar(spec, 0.035);
  EXPECT_GT(a35, std::min(a3, a4) * 0.5);
  EXPECT_LT(a35, std::max(a3, a4) * 2.0);
}

TEST(SimulateResonance, PsdIsTheAutocovariancesFourierSeries) {
  const kernels::Resonance r{0.25, 20.0, 30.0};
  const auto c = recursion_autocovariance(r, 20000);
  for (const double f : {1.0, 15.0, 19.7, 20.0, 20.4, 35.0, 49.0}) {
    const long double w = 2.0L * std::numbers::pi_v<long double> * f / kRate;
    long double s = c[0];
    for (std::size_t k = 1; k < c.size(); ++k)
      s += 2.0L * c[k] * std::cos(w * static_cast<long double>(k));
    EXPECT_NEAR(kernels::resonance_psd_one_sided(r, kRate, f) /
                    static_cast<double>(2.0L * s / kRate),
                1.0, 1e-9)
        << "f " << f;
  }
  // It integrates to sigma^2 over (0, Nyquist) (midpoint rule, fine against the 0.67 Hz width).
  double total = 0.0;
  constexpr int n = 200000;
  for (int i = 0; i < n; ++i)
    total += kernels::resonance_psd_one_sided(r, kRate, (i + 0.5) * 50.0 / n) * 50.0 / n;
  EXPECT_NEAR(total / (0.25 * 0.25), 1.0, 1e-6);
}

TEST(SimulateResonance, SimulationHasTheModelsMoments) {
  constexpr std::size_t n = 400000;
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.terms.N = 0.01;
  spec.resonances.push_back({0.2, 20.0, 40.0});
  spec.lowpass.cutoff_hz = 28.0;
  std::vector<double> y(n);
  kernels::simulate_channel(spec, 11, 3, y, 1);
  // Autocovariance at lags 0..6 of the resonance alone (N = 0): the estimate's standard deviation
  // is about sigma^2 sqrt(2 tau_coh / (n h)) with the coherence time tau_coh = q / (pi f0) =
  // 0.64 s, i.e. 1.6 % of sigma^2; 5 of them.
  kernels::ChannelSpec alone = spec;
  alone.terms = {};
  alone.lowpass = {};
  kernels::simulate_channel(alone, 11, 3, y, 1);
  const auto c = kernels::resonance_autocovariance(alone.resonances[0], kRate, 7);
  for (std::size_t k = 0; k < c.size(); ++k) {
    double s = 0.0;
    for (std::size_t i = 0; i + k < n; ++i)
      s += y[i] * y[i + k];
    EXPECT_NEAR(s / static_cast<double>(n - k), c[k], 5.0 * 0.016 * 0.04) << "lag " << k;
  }
  // The Allan variance of the filtered sum against model_avar_sampled: at m samples about
  // n / max(2 m, n_coh) independent second differences with n_coh = 2 tau_coh / h = 128 samples
  // where the resonance dominates, so a relative standard deviation of at most
  // sqrt(2 max(2 m, 128) / n); 5 of them.
  kernels::simulate_channel(spec, 11, 3, y, 2);
  const std::vector<std::int64_t> m{1, 2, 3, 4, 5, 8, 30, 100};
  const auto s =
      kernels::compute(kernels::Stat::Oadev, kernels::phase_from_rate(y, kRate, 1), m, 1);
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double want = kernels::model_avar_sampled(spec, m[i]);
    const double md = static_cast<double>(m[i]);
    const double tol = 5.0 * std::sqrt(2.0 * std::max(2.0 * md, 128.0) / n);
    EXPECT_NEAR(s.dev[i] * s.dev[i] / want, 1.0, tol) << "m " << m[i];
  }
}

TEST(SimulateResonance, SameBytesForAnyThreadCountAndBadSpecsRejected) {
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.terms.N = 0.01;
  spec.resonances.push_back({0.2, 20.0, 40.0});
  spec.resonances.push_back({0.1, 3.0, 2.0});
  spec.resonances.push_back({0.1, 30.0, 60.0, 0.5, 20.0});
  std::vector<double> a(70001), b(70001);
  kernels::simulate_channel(spec, 5, 1, a, 1);
  kernels::simulate_channel(spec, 5, 1, b, 2);
  EXPECT_EQ(a, b);
  for (const kernels::Resonance bad :
       {kernels::Resonance{-1.0, 20.0, 40.0}, kernels::Resonance{0.2, 50.0, 40.0},
        kernels::Resonance{0.2, 0.0, 40.0}, kernels::Resonance{0.2, 20.0, 0.4},
        kernels::Resonance{0.2, 20.0, NAN}, kernels::Resonance{0.2, 20.0, 40.0, -0.1, 10.0},
        kernels::Resonance{0.2, 20.0, 40.0, 4.1, 10.0},
        kernels::Resonance{0.2, 20.0, 40.0, 0.5, 0.0}}) {
    spec.resonances = {bad};
    EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
  }
  spec.resonances.assign(kernels::EffectTraits<kernels::Resonance>::max_count + 1, {0.1, 3.0, 2.0});
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
}

// A wandering resonance's Allan variance and PSD are one mixture: the Allan variance of m-sample
// averages is the integral of the one-sided PSD times 2 sin^4(pi f m h) / (m^2 sin^2(pi f h))
// over (0, Nyquist) (the transfer function of a difference of two adjacent m-sample means), a
// form resonance_avar does not use; the PSD holds sigma^2; the mixture's weights sum to 1 and a
// stationary resonance is its own one node.
TEST(SimulateResonance, WanderingAllanVarianceIsItsPsdsIntegral) {
  EXPECT_EQ(kernels::resonance_nodes({0.2, 20.0, 40.0}).size(), 1u);
  for (const double q : {40.0, 400.0}) {
    const kernels::Resonance r{0.25, 20.0, q, 0.6, 30.0};
    double weights = 0.0;
    for (const auto& node : kernels::resonance_nodes(r))
      weights += node.second;
    EXPECT_NEAR(weights, 1.0, 1e-12);
    constexpr int n = 400000;
    const double df = 50.0 / n;
    double total = 0.0;
    std::vector<double> f(n), psd(n, 0.0);
    for (int i = 0; i < n; ++i)
      f[static_cast<std::size_t>(i)] = (i + 0.5) * df;
    kernels::add_resonance_psd(r, kRate, 1.0, f, psd);
    for (const double s : psd)
      total += s * df;
    EXPECT_NEAR(total / (0.25 * 0.25), 1.0, 1e-6) << "q " << q;
    for (const int m : {1, 2, 3, 5, 8, 13, 40}) {
      double integral = 0.0;
      for (std::size_t i = 0; i < f.size(); ++i) {
        const double x = std::numbers::pi * f[i] / kRate;
        integral +=
            psd[i] * 2.0 * std::pow(std::sin(m * x), 4) / (m * m * std::pow(std::sin(x), 2)) * df;
      }
      EXPECT_NEAR(kernels::resonance_avar(r, kRate, static_cast<double>(m)) / integral, 1.0, 1e-5)
          << "q " << q << " m " << m;
    }
  }
}

// A simulated wandering resonance has the mixture's spectrum and Allan variance within what its
// record allows. 4000 s with a wander of 10 s (15 coherence times of q = 40 at 20 Hz, so the
// mixture holds) visit about T / (2 wander_s) = 200 independent frequencies:
//  - the share of the power within 0.3 Hz of f0 (Welch, 4096-sample segments) is about the share
//    of time the frequency spends near f0, p = 0.2 for the mixture; from 200 draws its relative
//    sd is sqrt(p (1 - p) / 200) / p = 14 %, and 4 of them (57 %) keep it far from a stationary
//    resonance's (2.8 times as much: the test fails when the simulation ignores the spread);
//  - the Allan variance at m samples: the relative variance var_f / (200 a^2) of the average of
//    avar_f(m) over the draws (the nodes' spread about the mixture's a) beside the narrowband
//    1 / (B T), B = pi f0 / q + 2 sqrt(pi) spread; 5 of their combined sd.
TEST(SimulateResonance, SimulatedWanderHasTheMixturesSpectrumAndAllanVariance) {
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.resonances.push_back({0.2, 20.0, 40.0, 1.0, 10.0});
  const kernels::Resonance& r = spec.resonances[0];
  constexpr std::size_t n = 400000;
  std::vector<double> y(n);
  kernels::simulate_channel(spec, 17, 2, y, 1);
  const double t = static_cast<double>(n) / kRate, draws = t / (2.0 * r.wander_s);
  const kernels::PsdResult psd = kernels::PsdPlan(4096).welch(y, kRate, 1);
  std::vector<double> f(psd.size()), want(psd.size(), 0.0);
  for (std::size_t k = 0; k < f.size(); ++k)
    f[k] = static_cast<double>(k) * psd.df_hz;
  kernels::add_resonance_psd(r, kRate, 1.0, f, want);
  const auto share = [&](const std::vector<double>& s) {
    double near = 0.0, all = 0.0;
    for (std::size_t k = 1; k < f.size(); ++k) {
      all += s[k];
      near += std::abs(f[k] - 20.0) <= 0.3 ? s[k] : 0.0;
    }
    return near / all;
  };
  const double p = share(want);
  EXPECT_NEAR(share(psd.psd) / p, 1.0, 4.0 * std::sqrt(p * (1.0 - p) / draws) / p);
  const double band = std::numbers::pi * 20.0 / 40.0 + 2.0 * std::sqrt(std::numbers::pi) * 1.0;
  const std::vector<std::int64_t> ms{1, 2, 3, 5, 8, 13};
  const auto got =
      kernels::compute(kernels::Stat::Oadev, kernels::phase_from_rate(y, kRate, 1), ms, 1);
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const auto m = static_cast<double>(ms[i]);
    const double a = kernels::resonance_avar(r, kRate, m);
    double var_f = 0.0;
    for (const auto& [node, w] : kernels::resonance_nodes(r))
      var_f += w * std::pow(kernels::resonance_avar(node, kRate, m) - a, 2);
    const double sd = std::sqrt(1.0 / (band * t) + var_f / (draws * a * a));
    EXPECT_NEAR(got.dev[i] * got.dev[i] / a, 1.0, 5.0 * sd) << "m " << m;
  }
}

}  // namespace
}  // namespace allanlot
