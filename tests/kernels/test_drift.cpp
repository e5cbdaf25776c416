// Frequency drift (kernels/drift/drift.hpp): a linear drift recovered from simulated clocks
// within its sigma, with the sigma checked against the one the true noise gives; the phase
// parabola against a naive long-double least squares; log and diffusion on noise-free data.
#include "kernels/drift/drift.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

using kernels::DataType;
using kernels::DriftModel;

// The test's own generator, independent of kernels/simulate: white FM of sigma `white` plus
// random-walk FM made by summing white noise of sigma `walk`, plus the drift `drift` t.
std::vector<double> clock_frequency(std::size_t n, double tau0, double white, double walk,
                                    double drift, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double rw = 0;
  for (std::size_t i = 0; i < n; ++i) {
    rw += walk * g(rng);
    y[i] = 1e-9 + drift * static_cast<double>(i) * tau0 + white * g(rng) + rw;
  }
  return y;
}

// The sigma of the least-squares slope under the true noise: its weights on the samples put
// through the same functional_variance the kernel uses, with the generator's own levels.
double true_slope_sigma(std::size_t n, double tau0, double white, double walk) {
  double tm = 0, s2 = 0;
  for (std::size_t i = 0; i < n; ++i)
    tm += static_cast<double>(i) * tau0;
  tm /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i)
    s2 += std::pow(static_cast<double>(i) * tau0 - tm, 2);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i)
    v[i] = (static_cast<double>(i) * tau0 - tm) / s2;
  return std::sqrt(kernels::functional_variance(v, {}, {0, white * white, walk * walk}));
}

TEST(Drift, LinearDriftWithinThreeSigmaOnSimulatedClocks) {
  constexpr std::size_t n = 4096;
  constexpr double tau0 = 1.0, white = 1e-11, walk = 2e-13, drift = 3e-15;
  const double sigma_true = true_slope_sigma(n, tau0, white, walk);
  int within = 0;
  double sum_z2 = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const auto y = clock_frequency(n, tau0, white, walk, drift, seed);
    const kernels::DriftFit f = kernels::fit_drift(y, DataType::Rate, tau0, DriftModel::Linear);
    ASSERT_EQ(f.names[1], "drift");
    const double z = (f.value[1] - drift) / f.sigma[1];
    within += std::abs(z) <= 3;
    sum_z2 += z * z;
    // The sigma rests on the random-walk level fitted to the residuals' Allan variance (plus one
    // standard error), whose longest taus carry few degrees of freedom: over 400 seeds of this
    // clock its ratio to the true sigma spans 0.47 to 1.60 (p0.5 0.63, p99.5 1.47;
    // docs/validation/2026-11-28-drift.md). [0.4, 2] holds every seed there and fails a sigma
    // that ignores the walk (0.15 of the true one) or a conservative one twice too large.
    EXPECT_GT(f.sigma[1] / sigma_true, 0.4) << "seed " << seed;
    EXPECT_LT(f.sigma[1] / sigma_true, 2.0) << "seed " << seed;
  }
  // An honest sigma misses 3 sigma with probability 0.0027: two misses in six, 1e-4.
  EXPECT_GE(within, 5);
  // And the six z's are standard normal: their sum of squares is chi-square with 6 degrees of
  // freedom, inside [0.381, 22.46] (its 0.1 % and 99.9 % points) unless sigma is off.
  EXPECT_GT(sum_z2, 0.381);
  EXPECT_LT(sum_z2, 22.46);
}

TEST(Drift, WhiteNoiseSigmaIgnoringTheWalkWouldBeTooSmall) {
  // The reason for the noise model: with random-walk FM the white-residual formula's sigma is
  // several times too small, and the fitted model sees the walk.
  constexpr std::size_t n = 4096;
  const auto y = clock_frequency(n, 1.0, 1e-11, 2e-13, 0.0, 7);
  const kernels::DriftFit f = kernels::fit_drift(y, DataType::Rate, 1.0, DriftModel::Linear);
  const double white_only = true_slope_sigma(n, 1.0, 1e-11, 0.0);
  EXPECT_GT(f.sigma[1], 3 * white_only);
  EXPECT_GT(f.noise.rw_fm, 0.0);
}

// Naive normal equations of x = a + b t + c t^2 / 2 in long double with raw t, solved by
// Gaussian elimination with partial pivoting.
std::vector<long double> naive_quadratic(const std::vector<double>& x, double tau0) {
  long double m[3][4] = {};
  for (std::size_t i = 0; i < x.size(); ++i) {
    const long double t = static_cast<long double>(i) * tau0;
    const long double g[3] = {1.0L, t, t * t / 2};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        m[r][c] += g[r] * g[c];
      m[r][3] += g[r] * x[i];
    }
  }
  for (int p = 0; p < 3; ++p) {
    int best = p;
    for (int r = p + 1; r < 3; ++r)
      if (std::fabs(m[r][p]) > std::fabs(m[best][p])) best = r;
    for (int c = 0; c < 4; ++c)
      std::swap(m[p][c], m[best][c]);
    for (int r = 0; r < 3; ++r) {
      if (r == p) continue;
      const long double f = m[r][p] / m[p][p];
      for (int c = 0; c < 4; ++c)
        m[r][c] -= f * m[p][c];
    }
  }
  return {m[0][3] / m[0][0], m[1][3] / m[1][1], m[2][3] / m[2][2]};
}

TEST(Drift, PhaseParabolaAgreesWithNaiveLongDoubleLeastSquares) {
  constexpr std::size_t n = 2000;
  constexpr double tau0 = 10.0;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double walk = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * tau0;
    walk += 1e-10 * tau0 * g(rng);
    x[i] = 2e-8 + 5e-11 * t + 4e-16 * t * t / 2 + 1e-10 * g(rng) + walk;
  }
  const kernels::DriftFit f = kernels::fit_drift(x, DataType::Phase, tau0, DriftModel::Quadratic);
  const auto ref = naive_quadratic(x, tau0);
  ASSERT_EQ(f.value.size(), 3u);
  // The naive normal equations in raw t lose about log10(cond) ~ 10 of long double's 19 digits.
  for (int p = 0; p < 3; ++p)
    EXPECT_NEAR(f.value[p], static_cast<double>(ref[p]),
                1e-8 * std::fabs(static_cast<double>(ref[p])))
        << f.names[p];
  EXPECT_EQ(f.names[2], "drift");
  EXPECT_TRUE(std::isfinite(f.sigma[2]) && f.sigma[2] > 0);
}

TEST(Drift, LogAndDiffusionRecoverNoiseFreeModels) {
  constexpr std::size_t n = 3000;
  std::vector<double> lg(n), df(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    lg[i] = 2e-9 * std::log1p(0.01 * t) + 1e-8;
    df[i] = 1e-8 + 3e-10 * std::sqrt(t + 50.0);
  }
  const auto l = kernels::fit_drift(lg, DataType::Rate, 1.0, DriftModel::Log);
  EXPECT_NEAR(l.value[0], 2e-9, 1e-13);
  EXPECT_NEAR(l.value[1], 0.01, 1e-6);
  EXPECT_NEAR(l.value[2], 1e-8, 1e-13);
  const auto d = kernels::fit_drift(df, DataType::Rate, 1.0, DriftModel::Diffusion);
  EXPECT_NEAR(d.value[0], 1e-8, 1e-12);
  EXPECT_NEAR(d.value[1], 3e-10, 1e-13);
  EXPECT_NEAR(d.value[2], 50.0, 0.05);
}

TEST(Drift, RemovalLeavesTheOffsetAndClearsTheSlope) {
  std::vector<double> y(100);
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] = 5.0 + 0.25 * static_cast<double>(i);
  y[10] = std::nan("");
  auto f = kernels::fit_drift(y, DataType::Rate, 1.0, DriftModel::Linear);
  kernels::remove_drift(y, 1.0, f);
  EXPECT_TRUE(std::isnan(y[10]));
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (i != 10) {
      EXPECT_NEAR(y[i], 5.0, 1e-12);
    }
  }
}

TEST(Drift, ModelsAndDataTypes) {
  EXPECT_EQ(kernels::parse_drift_model("diffusion"), DriftModel::Diffusion);
  EXPECT_THROW(kernels::parse_drift_model("cubic"), std::invalid_argument);
  EXPECT_EQ(kernels::drift_model_for(DriftModel::Linear, DataType::Phase), DriftModel::Quadratic);
  EXPECT_EQ(kernels::drift_model_for(DriftModel::Quadratic, DataType::Rate), DriftModel::Linear);
  const std::vector<double> few(5, 1.0);
  EXPECT_THROW(kernels::fit_drift(few, DataType::Rate, 1.0, DriftModel::Linear),
               std::invalid_argument);
  const std::vector<double> y(50, 1.0);
  EXPECT_THROW(kernels::fit_drift(y, DataType::Phase, 1.0, DriftModel::Log), std::invalid_argument);
  EXPECT_THROW(kernels::fit_drift(y, DataType::Rate, 0.0, DriftModel::Linear),
               std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
