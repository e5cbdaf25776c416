// The ramp's witness (kernels::find_trend): the variance of a record's
// least-squares slope under a model, against closed forms, a direct long-double sum and
// simulated records, and the witness's false alarm and power.
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

kernels::ChannelSpec model(double rate_hz) {
  kernels::ChannelSpec s;
  s.rate_hz = rate_hz;
  return s;
}

// The closed forms of var b = 36 / (pi T^3) int S(x / (pi T)) j1(x)^2 dx for the power laws:
// int j1^2 = pi / 6, int j1^2 / x = 1 / 4 and int j1^2 / x^2 = pi / 15 (checked by quadrature
// with scipy), so white FM gives 12 N^2 / T^3, flicker 9 B^2 / (pi T^2) and a random walk
// 6 K^2 / (5 T), the slope of Brownian motion. The integral's tail is approximated beyond
// x = 400 (error O(1e-6) relative): 1e-4 holds.
TEST(TrendSlopeVariance, MatchesThePowerLawsClosedForms) {
  const double t = 3600.0, pi = std::numbers::pi;
  auto s = model(100.0);
  s.terms.N = 0.02;
  EXPECT_NEAR(kernels::trend_slope_variance(s, t) / (12 * 0.02 * 0.02 / (t * t * t)), 1.0, 1e-4);
  s = model(100.0);
  s.terms.B = 0.003;
  EXPECT_NEAR(kernels::trend_slope_variance(s, t) / (9 * 0.003 * 0.003 / (pi * t * t)), 1.0, 1e-4);
  s = model(100.0);
  s.terms.K = 1e-4;
  EXPECT_NEAR(kernels::trend_slope_variance(s, t) / (6 * 1e-8 / (5 * t)), 1.0, 1e-4);
}

// A Gauss-Markov process against the direct sum over sample pairs, in long double, of
// w_j w_k sigma^2 phi^|j-k| (the simulator's AR(1), phi = exp(-1 / (tau_c rate))) with the
// least-squares weights w_k. The integral uses the continuous process's spectrum and the
// continuous weight, which differ from the sampled ones at frequencies near the rate, where the
// slope's weight is 1e-9 of its peak: 3e-6 apart here, 1e-3 holds.
TEST(TrendSlopeVariance, GaussMarkovMatchesTheDirectSum) {
  const double rate = 10.0, tau_c = 20.0, sigma = 0.3;
  const std::size_t n = 4000;
  auto s = model(rate);
  s.markovs.push_back({sigma, tau_c});
  const long double phi = std::exp(-1.0L / (tau_c * rate));
  std::vector<long double> w(n);
  long double stt = 0.0L;
  for (std::size_t k = 0; k < n; ++k) {
    w[k] = (static_cast<long double>(k) + 0.5L - 0.5L * n) / rate;
    stt += w[k] * w[k];
  }
  long double var = 0.0L, phi_lag = 1.0L;
  for (std::size_t lag = 0; lag < n; ++lag, phi_lag *= phi) {
    long double a = 0.0L;
    for (std::size_t k = 0; k + lag < n; ++k)
      a += w[k] * w[k + lag];
    var += (lag == 0 ? 1.0L : 2.0L) * phi_lag * a;
  }
  var *= static_cast<long double>(sigma) * sigma / (stt * stt);
  const double ratio = kernels::trend_slope_variance(s, n / rate) / static_cast<double>(var);
  EXPECT_NEAR(ratio, 1.0, 1e-3);
}

// Simulated records of white and random-walk rate noise: the slopes' variance over R records is
// the model's within 5 standard deviations of a variance estimate of R - 1 degrees of freedom,
// 5 sqrt(2 / (R - 1)); the witness fires on about false_alarm of them.
TEST(FindTrend, SimulatedSlopesHaveTheModelsSpread) {
  auto s = model(100.0);
  s.terms.N = 0.01;
  s.terms.K = 2e-4;
  const std::size_t n = 20000, reps = 400;
  const double predicted = kernels::trend_slope_variance(s, n / 100.0);
  std::vector<double> y(n);
  double sum2 = 0.0;
  int found = 0;
  for (std::uint64_t r = 0; r < reps; ++r) {
    kernels::simulate_channel(s, 4300, r, y, 1);
    const kernels::TrendWitness w = kernels::find_trend(y, 100.0, s, 0.01);
    ASSERT_TRUE(w.searched);
    EXPECT_DOUBLE_EQ(w.sigma * w.sigma, predicted);
    sum2 += w.slope * w.slope;
    found += w.found ? 1 : 0;
  }
  EXPECT_NEAR(sum2 / reps / predicted, 1.0, 5.0 * std::sqrt(2.0 / (reps - 1)));
  // Binomial(400, 0.01): mean 4, sd 2; at most 12 is 4 sd.
  EXPECT_LE(found, 12);
}

TEST(FindTrend, ARampOfSixSigmaIsFound) {
  auto s = model(100.0);
  s.terms.N = 0.01;
  s.terms.B = 0.003;
  const std::size_t n = 60000;
  const double sd = std::sqrt(kernels::trend_slope_variance(s, n / 100.0));
  auto truth = s;
  truth.terms.R = 6.0 * sd;
  std::vector<double> y(n);
  int found = 0;
  for (std::uint64_t r = 0; r < 20; ++r) {
    kernels::simulate_channel(truth, 4301, r, y, 1);
    const kernels::TrendWitness w = kernels::find_trend(y, 100.0, s, 1e-3);
    found += w.found ? 1 : 0;
    EXPECT_NEAR(std::abs(w.slope), 6.0 * sd, 4.0 * sd);
  }
  // At z = 6 against a threshold of 3.29 the power is 1 - Phi(-2.7) = 0.997 a record.
  EXPECT_GE(found, 19);
}

TEST(FindTrend, GapsAndBadArguments) {
  auto s = model(100.0);
  s.terms.N = 0.01;
  std::vector<double> y(100, 0.0);
  y[7] = std::nan("");
  EXPECT_FALSE(kernels::find_trend(y, 100.0, s).searched);
  EXPECT_FALSE(kernels::find_trend(std::vector<double>(2, 0.0), 100.0, s).searched);
  EXPECT_THROW(kernels::find_trend(y, 0.0, s), std::invalid_argument);
  EXPECT_THROW(kernels::find_trend(y, 100.0, s, 1.0), std::invalid_argument);
  EXPECT_THROW(kernels::trend_slope_variance(s, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
