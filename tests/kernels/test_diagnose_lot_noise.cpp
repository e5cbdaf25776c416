// kernels/diagnose/lot_noise.hpp: the chance that a complete model's channel lies beyond its
// replicas' p95, and of a lot's count of such channels, checked against simulated lots and
// against direct sums in long double.
#include "kernels/common/quantile.hpp"
#include "kernels/diagnose/lot_noise.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

// The share of simulated channels whose fresh draw lies beyond the 95 % threshold of `replicas`
// draws of the same distribution (`draw` maps a uniform to it), as diagnose judges a gap, the
// threshold computed by `quantile` from the sorted draws.
template <class Draw, class Quantile>
double simulated_beyond(int replicas, int channels, Draw draw, Quantile quantile) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> g(static_cast<std::size_t>(replicas));
  int beyond = 0;
  for (int c = 0; c < channels; ++c) {
    for (double& x : g)
      x = draw(u(rng));
    std::sort(g.begin(), g.end());
    beyond += draw(u(rng)) > quantile(g, 0.95) ? 1 : 0;
  }
  return static_cast<double>(beyond) / channels;
}

double uniform(double x) {
  return x;
}
double exponential(double x) {
  return -std::log1p(-x);
}

// 200,000 simulated channels give a share within sqrt(p (1 - p) / n) = 0.0005 to 0.0006 of its
// expectation (1 sd); 4 sd bound it.
constexpr int kChannels = 200000;
const double kShareSd = std::sqrt(0.079 * 0.921 / kChannels);

TEST(LotNoise, AChannelIsBeyondItsReplicasP95FivePercentOfTheTime) {
  // 30 replicas: the threshold lies between the 29th and 30th sorted draws (h = 0.95 * 31 - 1 =
  // 28.45), so a fresh draw is beyond it with probability (30 - 28 - 0.45) / 31 = 0.05; below
  // 19 replicas the threshold is the largest draw, beyond which a fresh one lies 1 / (R + 1) of
  // the time.
  EXPECT_NEAR(kernels::beyond_p95_probability(30), 0.05, 1e-15);
  EXPECT_NEAR(kernels::beyond_p95_probability(19), 0.05, 1e-15);
  EXPECT_NEAR(kernels::beyond_p95_probability(10), 1.0 / 11.0, 1e-15);
  EXPECT_NEAR(kernels::beyond_p95_probability(1), 0.5, 1e-15);
  EXPECT_TRUE(std::isnan(kernels::beyond_p95_probability(0)));
  for (const int r : {10, 30, 100}) {
    SCOPED_TRACE(r);
    EXPECT_NEAR(simulated_beyond(r, kChannels, uniform, kernels::exceedance_quantile_sorted),
                kernels::beyond_p95_probability(r), 4.0 * kShareSd);
  }
  // Where the position is whole (R = 39: the 38th of 39) the share is 0.05 for any continuous
  // distribution; between positions (R = 30) the interpolation between two draws is not that
  // between their probabilities, and for a skewed distribution (gaps are, a chi-square-like
  // tail) the share lies between the neighbours' (R - lo - 1) / (R + 1) = 0.032 and
  // (R - lo) / (R + 1) = 0.065, near 0.05 (0.0448 for an exponential and a chi-square of 8
  // degrees of freedom, in a numpy check of 200,000 channels).
  EXPECT_NEAR(simulated_beyond(39, kChannels, exponential, kernels::exceedance_quantile_sorted),
              0.05, 4.0 * kShareSd);
  const double skewed =
      simulated_beyond(30, kChannels, exponential, kernels::exceedance_quantile_sorted);
  EXPECT_GT(skewed, 1.0 / 31.0);
  EXPECT_LT(skewed, 2.0 / 31.0);
  EXPECT_NEAR(skewed, 0.0448, 4.0 * kShareSd);
}

TEST(LotNoise, TheVerdictsThresholdSitsAtThePlottingPosition) {
  // Sorted values 1 .. R: the 0.95 threshold is at position 0.95 (R + 1) (1-based), the value
  // itself; clamped to the largest below R = 19 and to the smallest for a tiny p.
  std::vector<double> v(30);
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = static_cast<double>(i + 1);
  EXPECT_NEAR(kernels::exceedance_quantile_sorted(v, 0.95), 0.95 * 31.0, 1e-12);
  EXPECT_NEAR(kernels::exceedance_quantile_sorted(v, 0.5), 15.5, 1e-12);
  EXPECT_EQ(kernels::exceedance_quantile_sorted(v, 0.01), 1.0);
  v.resize(10);
  EXPECT_EQ(kernels::exceedance_quantile_sorted(v, 0.95), 10.0);
  v.resize(1);
  EXPECT_EQ(kernels::exceedance_quantile_sorted(v, 0.95), 1.0);
  EXPECT_TRUE(std::isnan(kernels::exceedance_quantile_sorted(std::vector<double>{}, 0.95)));
}

TEST(LotNoise, TheSamplesOwnP95IsExceededMoreOftenThanFivePercent) {
  // Why the verdict does not use quantile_sorted (linear interpolation at h = 0.95 (R - 1),
  // the sample's description): from 30 replicas it lies between the 28th and 29th draws, and a
  // complete model's record exceeds it with probability (30 - 27.55) / 31 = 0.079.
  EXPECT_NEAR(simulated_beyond(30, kChannels, uniform, kernels::quantile_sorted), 2.45 / 31.0,
              4.0 * kShareSd);
}

long double choose(int n, int k) {
  long double c = 1.0L;
  for (int i = 1; i <= k; ++i)
    c = c * static_cast<long double>(n - k + i) / static_cast<long double>(i);
  return c;
}

TEST(LotNoise, AtLeastProbabilityIsTheBinomialAndPoissonBinomialTail) {
  // Equal probabilities: the binomial tail summed directly in long double.
  const int n = 30;
  const double p = kernels::beyond_p95_probability(30);
  const std::vector<double> ps(n, p);
  for (int k = 0; k <= n + 1; ++k) {
    long double tail = 0.0L;
    for (int j = k; j <= n; ++j)
      tail += choose(n, j) * std::pow(static_cast<long double>(p), j) *
              std::pow(1.0L - static_cast<long double>(p), n - j);
    EXPECT_NEAR(kernels::at_least_probability(ps, k), static_cast<double>(k <= 0 ? 1.0L : tail),
                1e-14)
        << k;
  }
  // 4 or more of 30 complete channels beyond their p95: about one lot in 16 (scipy's
  // binom.sf(3, 30, 0.05) = 0.06077); none beyond: 0.95^30 = 0.2146.
  EXPECT_NEAR(kernels::at_least_probability(ps, 4), 0.06077, 5e-5);
  EXPECT_NEAR(1.0 - kernels::at_least_probability(ps, 1), 0.21464, 5e-5);
  // Unequal probabilities (channels with different replica counts): every subset of 12 trials
  // enumerated in long double.
  const std::vector<double> q = {0.02, 0.5,  0.079, 0.11, 0.3,  0.0,
                                 1.0,  0.66, 0.25,  0.05, 0.09, 0.4};
  std::vector<long double> count(q.size() + 1, 0.0L);
  for (unsigned mask = 0; mask < (1u << q.size()); ++mask) {
    long double pr = 1.0L;
    int hits = 0;
    for (std::size_t t = 0; t < q.size(); ++t) {
      const bool hit = (mask >> t) & 1u;
      pr *= hit ? q[t] : 1.0L - q[t];
      hits += hit ? 1 : 0;
    }
    count[static_cast<std::size_t>(hits)] += pr;
  }
  for (int k = 1; k <= static_cast<int>(q.size()); ++k) {
    long double tail = 0.0L;
    for (std::size_t j = static_cast<std::size_t>(k); j < count.size(); ++j)
      tail += count[j];
    EXPECT_NEAR(kernels::at_least_probability(q, k), static_cast<double>(tail), 1e-14) << k;
  }
  EXPECT_THROW(kernels::at_least_probability(std::vector<double>{0.5, 1.5}, 1),
               std::invalid_argument);
  EXPECT_THROW(kernels::at_least_probability(std::vector<double>{NAN}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
