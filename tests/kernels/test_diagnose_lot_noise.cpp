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

// The share of simulated channels whose fresh draw lies beyond the p95 of `replicas` draws of
// the same distribution (`draw` maps a uniform to it), as diagnose judges a gap.
template <class Draw>
double simulated_beyond(int replicas, int channels, Draw draw) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> g(static_cast<std::size_t>(replicas));
  int beyond = 0;
  for (int c = 0; c < channels; ++c) {
    for (double& x : g)
      x = draw(u(rng));
    std::sort(g.begin(), g.end());
    beyond += draw(u(rng)) > kernels::quantile_sorted(g, 0.95) ? 1 : 0;
  }
  return static_cast<double>(beyond) / channels;
}

TEST(LotNoise, AChannelIsBeyondItsReplicasP95MoreOftenThanFivePercent) {
  // 30 replicas: the p95 lies between the 28th and 29th sorted draws (h = 27.55), so a fresh
  // draw is beyond it with probability (30 - 27 - 0.55) / 31.
  EXPECT_NEAR(kernels::beyond_p95_probability(30), 2.45 / 31.0, 1e-15);
  EXPECT_NEAR(kernels::beyond_p95_probability(2), (2.0 - 0.0 - 0.95) / 3.0, 1e-15);
  EXPECT_TRUE(std::isnan(kernels::beyond_p95_probability(1)));
  // Against simulated channels: 200,000 of them give the share within sqrt(p (1 - p) / n) =
  // 0.0006 (1 sd); 4 sd bound it. Exact for a uniform distribution; for a skewed one (gaps
  // are, a chi-square-like tail) the interpolation between two draws is not that between
  // their probabilities, so the share lies between the two neighbours' (R - lo - 1) / (R + 1)
  // = 0.0645 and (R - lo) / (R + 1) = 0.0968, and near the formula (0.0757 for an
  // exponential, 0.0753 for a chi-square of 8 degrees of freedom, in a numpy check).
  constexpr int kChannels = 200000;
  const double sd = std::sqrt(0.079 * 0.921 / kChannels);
  for (const int r : {10, 30, 100}) {
    SCOPED_TRACE(r);
    const double p = kernels::beyond_p95_probability(r);
    EXPECT_NEAR(simulated_beyond(r, kChannels, [](double x) { return x; }), p, 4.0 * sd);
  }
  const double skewed = simulated_beyond(30, kChannels, [](double x) { return -std::log1p(-x); });
  EXPECT_GT(skewed, 2.0 / 31.0);
  EXPECT_LT(skewed, 3.0 / 31.0);
  EXPECT_NEAR(skewed, kernels::beyond_p95_probability(30), 0.006);
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
  // 4 or more of 30 complete channels beyond their p95: about one lot in five.
  EXPECT_NEAR(kernels::at_least_probability(ps, 4), 0.2096, 5e-4);
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
