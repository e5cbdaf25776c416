// Tests of the eq. (3) fit (kernels/model/fit.hpp): the covariance model of the overlapping Allan
// estimates against direct sums and against Greenhall & Riley's edf, exact recovery of
// noise-free curves, agreement of QR with COD and SVD, rank and data statuses, preconditions,
// reuse of the plan, thread invariance, and a paper-level simulated gyro.
#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

using kernels::Eq3Fit;
using kernels::FitInput;
using kernels::FitResult;
using kernels::FitStatus;
using kernels::kNumTerms;
using kernels::Term;
using Theta = std::array<double, kNumTerms>;

constexpr int kR = 0, kK = 1, kB = 2, kN = 3, kQ = 4;

Theta theta_of(double r, double k, double b, double n, double q) {
  return {r * r, k * k, b * b, n * n, q * q};
}

// n = N + 1 - 2m terms of the overlapping estimator on N rate samples.
std::vector<std::int64_t> full_terms(const std::vector<std::int64_t>& m, std::int64_t n_samples) {
  std::vector<std::int64_t> n;
  for (const auto mi : m)
    n.push_back(n_samples + 1 - 2 * mi);
  return n;
}

// ------------------------------------------------------------------------------------------
// Covariance model.

// Generalized autocovariance of the phase per unit theta (the header's table), long double.
long double g_term(int term, long double t) {
  const long double a = std::fabs(t);
  switch (term) {
  case kN:
    return -a / 2;
  case kB:
    return a == 0 ? 0.0L : t * t * std::log(a) / (2 * std::numbers::pi_v<long double>);
  case kK:
    return a * a * a / 12;
  case kQ:
    return a == 0 ? 1.0L : 0.0L;
  }
  return 0;
}

// Reference: the plain sum over every lag of n(l) c(l)^2 (and n(l) c(l) for the ramp), in long
// double, for one random term plus an optional ramp.
long double reference_cov(int term, long double theta, long double theta_r, std::int64_t mi,
                          std::int64_t mj, std::int64_t ni, std::int64_t nj, double tau0) {
  const std::int64_t a[3] = {0, mi, 2 * mi}, b[3] = {0, mj, 2 * mj};
  const long double w[3] = {1, -2, 1};
  long double quad = 0, lin = 0;
  for (std::int64_t l = -(ni - 1); l <= nj - 1; ++l) {
    const long double np = std::min(ni, nj - l) - std::max<std::int64_t>(0, -l);
    if (np <= 0) continue;
    long double c = 0;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q)
        c += w[p] * w[q] * g_term(term, (long double)tau0 * (long double)(l + b[q] - a[p]));
    c *= theta;
    quad += np * c * c;
    lin += np * c;
  }
  const long double ti = mi * (long double)tau0, tj = mj * (long double)tau0;
  return 2 * quad / (4 * ti * ti * tj * tj * ni * nj) + theta_r * lin / ((long double)ni * nj);
}

TEST(OavarCovariance, MatchesPlainLagSumsForEveryTerm) {
  // Averaging factors that exercise exact summation (small m), the quadrature of long pieces
  // (m up to 700, pieces of length 100s) and the flicker tails out to 8000 lags; at these sizes
  // the plain sum is cheap. Tolerance, relative to sqrt(cov_ii cov_jj): N's pieces are cubic,
  // which the corrected midpoint rule sums exactly (1e-9: rounding of sums of 1e4 terms); K's
  // are of degree 7, leaving the Euler-Maclaurin remainder O(1/L^4) (1e-6); for flicker 1e-4
  // (that remainder next to the filter knots, the graded quadrature and the asymptotic tail).
  // All are a hundred times or more below what 1 % uncertainties need.
  const std::vector<std::int64_t> m = {1, 2, 3, 7, 40, 113, 700};
  const std::int64_t n_samples = 8000;
  const double tau0 = 0.01;
  const auto n = full_terms(m, n_samples);
  kernels::OavarCovariance cov;
  cov.prepare(m, n, tau0);
  for (const int term : {kN, kB, kK, kQ}) {
    for (const bool ramp : {false, true}) {
      Theta th{};
      th[static_cast<std::size_t>(term)] = 2.5;
      if (ramp) th[kR] = 0.7;
      Eigen::MatrixXd s;
      cov.assemble(th, s);
      const double tol = term == kB ? 1e-4 : term == kK ? 1e-6 : 1e-9;
      for (std::size_t i = 0; i < m.size(); ++i)
        for (std::size_t j = i; j < m.size(); ++j) {
          const long double ref =
              reference_cov(term, 2.5L, ramp ? 0.7L : 0.0L, m[i], m[j], n[i], n[j], tau0);
          const double got = s(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
          const long double scale =
              std::sqrt(std::fabs(reference_cov(term, 2.5L, 0, m[i], m[i], n[i], n[i], tau0) *
                                  reference_cov(term, 2.5L, 0, m[j], m[j], n[j], n[j], tau0)));
          EXPECT_NEAR(got, (double)ref, tol * (double)scale)
              << "term " << term << " ramp " << ramp << " m " << m[i] << "," << m[j];
        }
    }
  }
}

// The part of a curve the fit takes: the rows asked for from first_m on, with the columns the
// fit reads.
TEST(FitSubset, RowsFromFirstM) {
  kernels::StatResult r;
  r.m = {1, 2, 4, 8, 16};
  r.tau_s = {0.1, 0.2, 0.4, 0.8, 1.6};
  r.dev = {5, 4, 3, 2, 1};
  r.n = {99, 97, 93, 85, 69};
  r.edf = {90, 80, 60, 40, 20};
  const std::vector<std::size_t> rows = {0, 2, 3, 4};
  const kernels::StatResult a = kernels::fit_subset(r, rows, 4);
  EXPECT_EQ(a.m, (std::vector<std::int64_t>{4, 8, 16}));
  EXPECT_EQ(a.tau_s, (std::vector<double>{0.4, 0.8, 1.6}));
  EXPECT_EQ(a.dev, (std::vector<double>{3, 2, 1}));
  EXPECT_EQ(a.n, (std::vector<std::int64_t>{93, 85, 69}));
  EXPECT_EQ(a.edf, (std::vector<double>{60, 40, 20}));
  EXPECT_EQ(kernels::fit_subset(r, rows).m, (std::vector<std::int64_t>{1, 4, 8, 16}));
  EXPECT_EQ(kernels::fit_subset(r, 3).m, (std::vector<std::int64_t>{4, 8, 16}));
  EXPECT_EQ(kernels::fit_subset(r, 32).size(), 0u);
}

// The basis is built row by row on OpenMP threads, each entry alone: the same bits at 1, 2
// and 3 threads, for every term pair and the ramp's cross terms.
TEST(OavarCovariance, SameBitsForAnyThreadCount) {
  std::vector<std::int64_t> m;
  for (std::int64_t v = 1; v < 300000; v = v * 3 / 2 + 1)
    m.push_back(v);
  const auto n = full_terms(m, 1000000);
  kernels::OavarCovariance one;
  one.prepare(m, n, 1e-3, 1);
  Theta th{};
  th[kN] = 1.3, th[kB] = 0.4, th[kK] = 0.02, th[kQ] = 0.7, th[kR] = 0.01;
  Eigen::MatrixXd a, b;
  one.assemble(th, a);
  for (const int threads : {2, 3}) {
    kernels::OavarCovariance more;
    more.prepare(m, n, 1e-3, threads);
    more.assemble(th, b);
    ASSERT_EQ(a.rows(), b.rows());
    for (Eigen::Index i = 0; i < a.rows(); ++i)
      for (Eigen::Index j = 0; j < a.cols(); ++j)
        ASSERT_EQ(a(i, j), b(i, j)) << i << ", " << j << " at " << threads << " threads";
  }
}

TEST(OavarCovariance, WhiteAndRandomWalkFromExplicitPhaseCovariance) {
  // Independent of the generalized autocovariances: the phase covariance written out directly
  // (Brownian motion min(s, t) N^2 for white rate noise; integrated Brownian motion
  // K^2 (s^2 t / 2 - s^3 / 6), s <= t, for rate random walk) and the estimator's covariance
  // formed as 2 sum_kl cov(d_k, d_l)^2 / (4 tau_i^2 tau_j^2 M_i M_j) over every pair of terms.
  // Tolerance as in the test above: 1e-9 for N, 1e-6 for K.
  const std::int64_t n_samples = 90;
  const double tau0 = 0.5;
  const std::vector<std::int64_t> m = {1, 2, 5, 11, 20};
  const auto n = full_terms(m, n_samples);
  kernels::OavarCovariance cov;
  cov.prepare(m, n, tau0);
  for (const int term : {kN, kK}) {
    const auto cx = [&](std::int64_t k, std::int64_t l) -> long double {
      const long double s = std::min(k, l) * (long double)tau0;
      const long double t = std::max(k, l) * (long double)tau0;
      return term == kN ? s : s * s * t / 2 - s * s * s / 6;
    };
    Theta th{};
    th[static_cast<std::size_t>(term)] = 1.0;
    Eigen::MatrixXd s;
    cov.assemble(th, s);
    for (std::size_t i = 0; i < m.size(); ++i)
      for (std::size_t j = 0; j < m.size(); ++j) {
        const std::int64_t a[3] = {0, m[i], 2 * m[i]}, b[3] = {0, m[j], 2 * m[j]};
        const long double w[3] = {1, -2, 1};
        long double sum = 0;
        for (std::int64_t k = 0; k < n[i]; ++k)
          for (std::int64_t l = 0; l < n[j]; ++l) {
            long double c = 0;
            for (int p = 0; p < 3; ++p)
              for (int q = 0; q < 3; ++q)
                c += w[p] * w[q] * cx(k + a[p], l + b[q]);
            sum += c * c;
          }
        const long double ti = m[i] * (long double)tau0, tj = m[j] * (long double)tau0;
        const long double ref = 2 * sum / (4 * ti * ti * tj * tj * n[i] * n[j]);
        EXPECT_NEAR(s(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)), (double)ref,
                    (term == kN ? 1e-9 : 1e-6) * (double)std::fabs(ref))
            << "term " << term << " m " << m[i] << "," << m[j];
      }
  }
}

TEST(OavarCovariance, DiagonalAgreesWithGreenhallEdf) {
  // var(avar_hat) = 2 avar^2 / edf: the model's diagonal against Greenhall & Riley's edf
  // algorithm (kernels/uncertainty/edf.hpp, another implementation of the same theory, exact sums
  // for small m and fitted asymptotes beyond). Their asymptotes are quoted to a few 1e-3; 2 %
  // allows for that. Only m >= 64: below, Greenhall's continuous-time model of the phase differs
  // from sampled data by O(1/m) (at m = 1 for white rate noise it gives edf ~ 0.78 N where the
  // exact discrete value, which the explicit-covariance test above confirms and SP1065 Table 5
  // reproduces, is 2 N / 3).
  const std::int64_t n_samples = 1000000;
  const double tau0 = 1e-3;
  const std::vector<std::int64_t> m = {64, 200, 1000, 20000, 240000};
  const auto n = full_terms(m, n_samples);
  kernels::OavarCovariance cov;
  cov.prepare(m, n, tau0);
  const kernels::FiniteDifferenceKind oavar{2, true, false};
  for (const auto& [term, alpha] : std::vector<std::pair<int, int>>{{kN, 0}, {kB, -1}, {kK, -2}}) {
    Theta th{};
    th[static_cast<std::size_t>(term)] = 1.0;
    Eigen::MatrixXd s;
    cov.assemble(th, s);
    for (std::size_t i = 0; i < m.size(); ++i) {
      const double avar = kernels::eq3_avar(th, static_cast<double>(m[i]) * tau0);
      const auto ii = static_cast<Eigen::Index>(i);
      const double edf_model = 2 * avar * avar / s(ii, ii);
      const double edf_gr = kernels::edf_greenhall(alpha, oavar, m[i], n_samples + 1);
      EXPECT_NEAR(edf_model / edf_gr, 1.0, 0.02) << "alpha " << alpha << " m " << m[i];
    }
  }
}

TEST(OavarCovariance, NeighbouringTausAreStronglyCorrelated) {
  // The reason for the covariance model: at 16 taus per decade the estimates of neighbouring
  // taus share most of their data. For white rate noise the correlation exceeds 0.9.
  const std::vector<std::int64_t> m = {100, 115, 133};
  const auto n = full_terms(m, 100000);
  kernels::OavarCovariance cov;
  cov.prepare(m, n, 1e-3);
  Eigen::MatrixXd s;
  cov.assemble(theta_of(0, 0, 0, 1, 0), s);
  EXPECT_GT(s(0, 1) / std::sqrt(s(0, 0) * s(1, 1)), 0.9);
  EXPECT_GT(s(1, 2) / std::sqrt(s(1, 1) * s(2, 2)), 0.9);
}

// ------------------------------------------------------------------------------------------
// Noise-free fits.

struct Curve {
  std::vector<double> tau, avar, edf;
  std::vector<std::int64_t> m, n;
  double tau0 = 0;
  std::int64_t n_samples = 0;
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

// The model curve on a log grid (16 per decade) with Greenhall's white-FM edf (any positive
// edf would do for an exact curve; these are the weights a real curve would get).
Curve model_curve(const Theta& th, double rate_hz, std::int64_t n_samples) {
  Curve c;
  c.tau0 = 1.0 / rate_hz;
  c.n_samples = n_samples;
  c.m = kernels::make_m_list(kernels::parse_tau_grid("log:16"),
                             kernels::max_m(kernels::Stat::Oadev, n_samples + 1));
  c.n = full_terms(c.m, n_samples);
  for (const auto m : c.m) {
    const double tau = static_cast<double>(m) * c.tau0;
    c.tau.push_back(tau);
    c.avar.push_back(kernels::eq3_avar(th, tau));
    c.edf.push_back(kernels::edf_greenhall(0, {2, true, false}, m, n_samples + 1));
  }
  return c;
}

TEST(Eq3Fit, NoiseFreeCurveRecoversAllFiveCoefficients) {
  // Every term visible somewhere between 1 ms and 1350 s.
  const Theta truth = theta_of(2e-6, 3e-4, 1.2e-3, 5e-3, 2e-4);
  const Curve c = model_curve(truth, 1000.0, 5400000);
  Eq3Fit fit(c.tau.size());
  const FitResult r = fit.fit(c.input());
  ASSERT_EQ(r.status, FitStatus::Ok);
  EXPECT_EQ(r.rank, 5);
  for (int j = 0; j < kNumTerms; ++j) {
    EXPECT_NEAR(r.terms[static_cast<std::size_t>(j)].theta, truth[static_cast<std::size_t>(j)],
                1e-9 * truth[static_cast<std::size_t>(j)])
        << "term " << j;
    EXPECT_FALSE(r.terms[static_cast<std::size_t>(j)].at_bound);
  }
  EXPECT_LT(r.residual_norm, 1e-8);
  EXPECT_LT(r.chi2_dof, 1e-12);
  EXPECT_EQ(r.dof, static_cast<int>(c.tau.size()) - 5);
  for (std::size_t i = 0; i < c.tau.size(); ++i)
    EXPECT_NEAR(r.adev_model[i], std::sqrt(c.avar[i]), 1e-9 * std::sqrt(c.avar[i]));
}

TEST(Eq3Fit, AbsentTermsComeOutZeroAndUndetected) {
  // White + flicker only: R, K, Q are held at zero by the constraint (their free estimates
  // are 0 up to rounding), not detected, with finite upper bounds.
  const Theta truth = theta_of(0, 0, 1.25e-3, 5e-3, 0);
  const Curve c = model_curve(truth, 1000.0, 1000000);
  Eq3Fit fit;
  const FitResult r = fit.fit(c.input());
  ASSERT_EQ(r.status, FitStatus::Ok);
  EXPECT_NEAR(r[Term::N].value, 5e-3, 1e-9 * 5e-3);
  EXPECT_NEAR(r[Term::B].value, 1.25e-3, 1e-7 * 1.25e-3);
  EXPECT_TRUE(r[Term::N].detected);
  EXPECT_TRUE(r[Term::B].detected);
  for (const Term t : {Term::R, Term::K, Term::Q}) {
    EXPECT_FALSE(r[t].detected);
    EXPECT_LT(r[t].value, 1e-6 * std::sqrt(r[t].theta_sigma) + 1e-300);
    EXPECT_GT(r[t].upper, 0.0);
    EXPECT_TRUE(std::isfinite(r[t].upper));
    EXPECT_TRUE(std::isfinite(r[t].sigma));
  }
}

// Weighted least squares solved independently with COD and SVD (Eigen's pattern: two
// decompositions, one answer), with the weights the fit reports through its model curve.
TEST(Eq3Fit, QrAgreesWithCodAndSvd) {
  const Theta truth = theta_of(2e-6, 3e-4, 1.2e-3, 5e-3, 2e-4);
  Curve c = model_curve(truth, 1000.0, 5400000);
  // A deterministic +-1 % ripple so that the residual is not zero but every term stays free.
  for (std::size_t i = 0; i < c.avar.size(); ++i)
    c.avar[i] *= 1.0 + 0.01 * std::sin(1.7 * i);
  Eq3Fit fit;
  const FitResult r = fit.fit(c.input());
  // A 1 % ripple is far beyond the noise of a 5.4 M-sample curve: the fit says so, and its
  // coefficients are still the weighted least-squares solution compared below.
  ASSERT_EQ(r.status, FitStatus::PoorFit);
  EXPECT_GT(r.chi2_dof, 10.0);
  for (int j = 0; j < kNumTerms; ++j)
    ASSERT_FALSE(r.terms[static_cast<std::size_t>(j)].at_bound);
  const auto p = static_cast<Eigen::Index>(c.tau.size());
  Eigen::MatrixXd a(p, kNumTerms);
  Eigen::VectorXd b(p);
  Eigen::VectorXd scale(kNumTerms);
  for (Eigen::Index i = 0; i < p; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double sw = std::sqrt(c.edf[iu] / 2) / r.avar_model[iu];
    const auto g = kernels::eq3_regressors(c.tau[iu]);
    for (int j = 0; j < kNumTerms; ++j)
      a(i, j) = sw * g[static_cast<std::size_t>(j)];
    b(i) = sw * c.avar[iu];
  }
  for (int j = 0; j < kNumTerms; ++j) {
    scale(j) = 1.0 / a.col(j).norm();
    a.col(j) *= scale(j);
  }
  const Eigen::VectorXd x_cod = scale.cwiseProduct(a.completeOrthogonalDecomposition().solve(b));
  // Jacobi's SVD: Eigen's BDCSVD hands a matrix of fewer than 16 columns to it anyway, and
  // instantiating BDCSVD as well doubles this file's compile time under ASan.
  const Eigen::VectorXd x_svd =
      scale.cwiseProduct(a.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(b));
  for (int j = 0; j < kNumTerms; ++j) {
    const double got = r.terms[static_cast<std::size_t>(j)].theta;
    // The fit's own model-weighted solution is a fixed point: the weights come from it.
    EXPECT_NEAR(got, x_cod(j), 1e-8 * std::abs(x_cod(j))) << "term " << j;
    EXPECT_NEAR(got, x_svd(j), 1e-8 * std::abs(x_svd(j))) << "term " << j;
  }
}

TEST(Eq3Fit, TooFewTausIsRankDeficient) {
  const Theta truth = theta_of(0, 0, 1e-3, 5e-3, 0);
  for (const std::size_t keep : {1u, 3u, 4u}) {
    Curve c = model_curve(truth, 1000.0, 100000);
    c.tau.resize(keep);
    c.avar.resize(keep);
    c.edf.resize(keep);
    c.m.resize(keep);
    c.n.resize(keep);
    Eq3Fit fit;
    const FitResult r = fit.fit(c.input());
    EXPECT_EQ(r.status, FitStatus::RankDeficient);
    EXPECT_EQ(r.rank, static_cast<int>(keep));
  }
  // Five taus in a factor 1.004 of each other: distinct, yet numerically collinear.
  Curve c;
  c.tau0 = 1e-3;
  c.n_samples = 1000000;
  for (std::int64_t m = 1000; m < 1005; ++m) {
    c.m.push_back(m);
    c.tau.push_back(static_cast<double>(m) * c.tau0);
    c.avar.push_back(kernels::eq3_avar(truth, c.tau.back()));
    c.edf.push_back(100.0);
    c.n.push_back(c.n_samples + 1 - 2 * m);
  }
  Eq3Fit fit;
  const FitResult r = fit.fit(c.input());
  EXPECT_EQ(r.status, FitStatus::RankDeficient);
  EXPECT_LT(r.rank, 5);
}

TEST(Eq3Fit, NoDataStatus) {
  Eq3Fit fit;
  FitInput empty;
  empty.tau0_s = 1e-3;
  empty.n_samples = 10;
  EXPECT_EQ(fit.fit(empty).status, FitStatus::NoData);
  Curve c = model_curve(theta_of(0, 0, 1e-3, 5e-3, 0), 1000.0, 100000);
  std::fill(c.avar.begin(), c.avar.end(), 0.0);
  EXPECT_EQ(fit.fit(c.input()).status, FitStatus::NoData);
}

TEST(Eq3Fit, BrokenPreconditionsThrow) {
  const Curve good = model_curve(theta_of(0, 0, 1e-3, 5e-3, 0), 1000.0, 100000);
  Eq3Fit fit;
  const auto expect_throw = [&](auto mutate) {
    Curve c = good;
    FitInput in = c.input();
    mutate(c, in);
    EXPECT_THROW(fit.fit(in), std::invalid_argument);
  };
  expect_throw([](Curve& c, FitInput& in) {
    c.edf.pop_back();
    in.edf = c.edf;
  });
  expect_throw([](Curve& c, FitInput& in) {
    c.tau[0] = 0.0;
    in.tau_s = c.tau;
  });
  expect_throw([](Curve& c, FitInput& in) {
    std::swap(c.tau[2], c.tau[3]);
    in.tau_s = c.tau;
  });
  expect_throw([](Curve& c, FitInput& in) {
    c.tau[4] *= 1.0 + 1e-6;  // not a multiple of tau0
    in.tau_s = c.tau;
  });
  expect_throw([](Curve& c, FitInput& in) {
    c.avar[5] = std::nan("");
    in.values = c.avar;
  });
  expect_throw([](Curve& c, FitInput& in) {
    c.avar[5] = -1.0;
    in.values = c.avar;
  });
  expect_throw([](Curve& c, FitInput& in) {
    c.edf[1] = 0.0;
    in.edf = c.edf;
  });
  expect_throw([](Curve& c, FitInput& in) {
    c.n[1] = c.n_samples;  // more terms than the record has
    in.n = c.n;
  });
  expect_throw([](Curve&, FitInput& in) { in.tau0_s = -1.0; });
  expect_throw([](Curve&, FitInput& in) { in.n_samples = 0; });
  kernels::StatResult no_edf;
  no_edf.tau_s = {1.0};
  no_edf.m = {1};
  no_edf.dev = {1.0};
  no_edf.n = {5};
  EXPECT_THROW(fit.fit(no_edf, 1.0, 10), std::invalid_argument);
  EXPECT_THROW(Eq3Fit(0, kernels::FitOptions{.upper_confidence = 1.0}), std::invalid_argument);
}

// ------------------------------------------------------------------------------------------
// Simulated data.

struct Simulated {
  kernels::StatResult oadev;
  std::int64_t n_samples = 0;
  double tau0 = 0;
};

// simulate_channel -> phase_from_rate -> oadev on 16 taus per decade -> Stable32's edf
// (add_confidence). `burn` samples are simulated first and dropped, so that Kasdin's flicker
// filter, which starts at the first sample, has a past as long as the record (see
// simulate.hpp: the deficit is of relative order m / (length of the past)).
Simulated simulate(const kernels::NoiseTerms& terms, double rate_hz, std::size_t n,
                   std::uint64_t seed, std::size_t burn) {
  kernels::ChannelSpec spec;
  spec.rate_hz = rate_hz;
  spec.terms = terms;
  std::vector<double> y(n + burn);
  kernels::simulate_channel(spec, seed, 0, y);
  const auto p = kernels::phase_from_rate(std::span<const double>(y).subspan(burn), rate_hz);
  const auto m = kernels::make_m_list(kernels::parse_tau_grid("log:16"),
                                      kernels::max_m(kernels::Stat::Oadev, p.n_points()));
  Simulated s;
  s.oadev = kernels::oadev(p, m);
  kernels::add_confidence(kernels::Stat::Oadev, p, s.oadev);
  s.n_samples = static_cast<std::int64_t>(n);
  s.tau0 = 1.0 / rate_hz;
  return s;
}

TEST(Eq3FitSimulated, PaperGyroXLevels) {
  // The paper's gyro X (Table): N = 18 deg/h/sqrt(Hz) = 0.005 deg/s sqrt(s), B = 4.5 deg/h =
  // 0.00125 deg/s, K = 0.1 deg/h/sqrt(h) = 4.63e-7 deg/s/sqrt(s), no quantization, 1 kHz, 90 min
  // (5.4 M samples). K is far below anything 90 min can see (its term reaches 5e-5 of the
  // flicker floor at the longest tau), so it must come out undetected with an upper bound
  // above the truth.
  kernels::NoiseTerms t;
  t.N = 0.005;
  t.B = 0.00125;
  t.K = 4.63e-7;
  const Simulated s = simulate(t, 1000.0, 5400000, 20240917, 0);
  Eq3Fit fit;
  const FitResult r = fit.fit(s.oadev, s.tau0, s.n_samples);
  ASSERT_EQ(r.status, FitStatus::Ok);
  std::cout << "paper gyro X: N " << r[Term::N].value << " +- " << r[Term::N].sigma << ", B "
            << r[Term::B].value << " +- " << r[Term::B].sigma << ", K " << r[Term::K].value
            << " (upper " << r[Term::K].upper << "), Q " << r[Term::Q].value << " (upper "
            << r[Term::Q].upper << "), R upper " << r[Term::R].upper << ", chi2_dof " << r.chi2_dof
            << "; read-outs N(1 s) " << r.n_1s.value << " +- " << r.n_1s.sigma << " (model "
            << r.n_1s.model << "), B " << r.bias_instability.value << " +- "
            << r.bias_instability.sigma << " at " << r.bias_instability.tau_s << " s (model "
            << r.bias_instability.model << "), K " << r.k_3s.value << "\n";
  EXPECT_NEAR(r[Term::N].value, t.N, 0.05 * t.N);
  EXPECT_NEAR(r[Term::B].value, t.B, 0.25 * t.B);
  EXPECT_TRUE(r[Term::N].detected);
  EXPECT_TRUE(r[Term::B].detected);
  EXPECT_FALSE(r[Term::Q].detected);
  EXPECT_FALSE(r[Term::K].detected);
  EXPECT_GT(r[Term::K].upper, t.K);
  // The truth within 3 sigma (the coverage program checks the calibration properly).
  EXPECT_LT(std::abs(r[Term::N].value - t.N), 3 * r[Term::N].sigma);
  EXPECT_LT(std::abs(r[Term::B].value - t.B), 3 * r[Term::B].sigma);
  // The model explains the curve: chi2 / its expectation within a generous factor (the sum
  // has few effective degrees of freedom because the estimates are correlated).
  EXPECT_LT(r.chi2_dof, 3.0);
  // Read-outs: sigma(1 s) is N inflated by the flicker floor at 1 s (2.8 % of avar there), so
  // it must agree with the same read-out of the fitted curve, and exceed the fitted N.
  ASSERT_TRUE(r.n_1s.valid);
  EXPECT_NEAR(r.n_1s.value, r.n_1s.model, 3 * r.n_1s.sigma + 3 * r[Term::N].sigma);
  EXPECT_GT(r.n_1s.model, r[Term::N].value);
  ASSERT_TRUE(r.bias_instability.valid);
  EXPECT_NEAR(r.bias_instability.value, t.B, 0.25 * t.B);
  EXPECT_FALSE(r.k_3s.valid);  // the curve never turns up in 90 min
  EXPECT_GT(r.k_3s.value, t.K);
}

TEST(Eq3FitSimulated, PureWhiteReadoutMatchesFit) {
  // Pure white rate noise: sigma(1 s) sqrt(1 s) and the fitted N estimate the same thing; the
  // difference must be within the two uncertainties (3 sigma of the sum, conservative because
  // the two are positively correlated); B, K, R, Q undetected.
  kernels::NoiseTerms t;
  t.N = 0.01;
  const Simulated s = simulate(t, 100.0, 400000, 7, 0);
  Eq3Fit fit;
  const FitResult r = fit.fit(s.oadev, s.tau0, s.n_samples);
  ASSERT_EQ(r.status, FitStatus::Ok);
  ASSERT_TRUE(r.n_1s.valid);
  EXPECT_NEAR(r.n_1s.value, r[Term::N].value, 3 * (r.n_1s.sigma + r[Term::N].sigma));
  EXPECT_NEAR(r[Term::N].value, t.N, 3 * r[Term::N].sigma);
  for (const Term u : {Term::R, Term::K, Term::B, Term::Q})
    EXPECT_FALSE(r[u].detected);
  EXPECT_FALSE(r.bias_instability.valid);  // monotonic curve: no floor in it
}

TEST(Eq3FitSimulated, RandomWalkBranchReadout) {
  // White + rate random walk, with the +1/2 branch over the last 1.5 decades: the K read-out
  // is valid and agrees with the fitted K within the uncertainties plus the bias the fitted
  // curve predicts for it (its `model` value).
  kernels::NoiseTerms t;
  t.N = 0.01;
  t.K = 0.002;  // crossing at tau = sqrt(3) N / K = 8.7 s
  const Simulated s = simulate(t, 100.0, 400000, 11, 0);
  Eq3Fit fit;
  const FitResult r = fit.fit(s.oadev, s.tau0, s.n_samples);
  ASSERT_EQ(r.status, FitStatus::Ok);
  EXPECT_TRUE(r[Term::K].detected);
  EXPECT_NEAR(r[Term::K].value, t.K, 3 * r[Term::K].sigma);
  ASSERT_TRUE(r.k_3s.valid);
  EXPECT_NEAR(r.k_3s.value, r.k_3s.model, 3 * (r.k_3s.sigma + r[Term::K].sigma));
  EXPECT_GE(r.k_3s.model, r[Term::K].value);
}

TEST(Eq3Fit, ReusedPlanGivesIdenticalResultsAndHandlesNewShapes) {
  kernels::NoiseTerms t;
  t.N = 0.01;
  t.B = 0.003;
  const Simulated a = simulate(t, 100.0, 200000, 1, 0);
  const Simulated b = simulate(t, 100.0, 200000, 2, 0);
  const Simulated c = simulate(t, 100.0, 150000, 3, 0);
  Eq3Fit reused(a.oadev.size());
  const FitResult ra = reused.fit(a.oadev, a.tau0, a.n_samples);
  const FitResult rb = reused.fit(b.oadev, b.tau0, b.n_samples);
  const FitResult rc = reused.fit(c.oadev, c.tau0, c.n_samples);  // another shape
  const FitResult rb_again = reused.fit(b.oadev, b.tau0, b.n_samples);
  for (const auto& [got, sim] : std::vector<std::pair<const FitResult*, const Simulated*>>{
           {&ra, &a}, {&rb, &b}, {&rc, &c}, {&rb_again, &b}}) {
    Eq3Fit fresh;
    const FitResult want = fresh.fit(sim->oadev, sim->tau0, sim->n_samples);
    for (int j = 0; j < kNumTerms; ++j) {
      EXPECT_EQ(got->terms[static_cast<std::size_t>(j)].theta,
                want.terms[static_cast<std::size_t>(j)].theta);
      EXPECT_EQ(got->terms[static_cast<std::size_t>(j)].theta_sigma,
                want.terms[static_cast<std::size_t>(j)].theta_sigma);
    }
    EXPECT_EQ(got->chi2, want.chi2);
  }
}

#ifdef _OPENMP
TEST(Eq3Fit, SameBitsForAnyThreadCount) {
  // Eigen would parallelize large matrix products with OpenMP; the fit avoids them, so the
  // OpenMP thread count cannot change a bit of the result.
  const Theta truth = theta_of(2e-6, 3e-4, 1.2e-3, 5e-3, 2e-4);
  Curve c = model_curve(truth, 1000.0, 5400000);
  for (std::size_t i = 0; i < c.avar.size(); ++i)
    c.avar[i] *= 1.0 + 0.01 * std::cos(2.3 * i);
  const int saved = omp_get_max_threads();
  std::vector<FitResult> rs;
  for (const int threads : {1, 2, 7}) {
    omp_set_num_threads(threads);
    Eq3Fit fit;
    rs.push_back(fit.fit(c.input()));
  }
  omp_set_num_threads(saved);
  for (std::size_t k = 1; k < rs.size(); ++k) {
    for (int j = 0; j < kNumTerms; ++j) {
      EXPECT_EQ(rs[k].terms[static_cast<std::size_t>(j)].theta,
                rs[0].terms[static_cast<std::size_t>(j)].theta);
      EXPECT_EQ(rs[k].terms[static_cast<std::size_t>(j)].theta_sigma,
                rs[0].terms[static_cast<std::size_t>(j)].theta_sigma);
    }
    EXPECT_EQ(rs[k].chi2, rs[0].chi2);
  }
}
#endif

}  // namespace
}  // namespace allanlot
