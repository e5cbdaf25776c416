// The test of the given coefficients (kernels/diagnose/conclude.cpp, docs/diagnose.md "Wrong or
// incomplete"): its Satterthwaite match of the chi-square gain, exact where the taus are
// independent and calibrated on simulated correlated residuals, and on a complete model's record
// that the rounds' one scale found wrong.
#include "kernels/diagnose/internal.hpp"
#include "kernels/test_diagnose_support.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>

namespace allanlot {
namespace {

using namespace kernels::diagnose_detail;

constexpr Eigen::Index kTaus = 30;

// Columns as a curve's smooth regressors are: 1, x and x^2 on x = -1 .. 1 over the taus.
Eigen::MatrixXd smooth_columns(int k) {
  Eigen::MatrixXd a(kTaus, k);
  for (Eigen::Index i = 0; i < kTaus; ++i) {
    const double x = -1.0 + 2.0 * static_cast<double>(i) / static_cast<double>(kTaus - 1);
    for (Eigen::Index j = 0; j < k; ++j)
      a(i, j) = std::pow(x, static_cast<double>(j));
  }
  return a;
}

// Neighbouring taus of an overlapping Allan curve at 8 per decade are correlated about so.
Eigen::MatrixXd ar1_correlation(double rho) {
  Eigen::MatrixXd r(kTaus, kTaus);
  for (Eigen::Index i = 0; i < kTaus; ++i)
    for (Eigen::Index j = 0; j < kTaus; ++j)
      r(i, j) = std::pow(rho, static_cast<double>(std::abs(i - j)));
  return r;
}

TEST(DiagnoseRevision, IndependentTausGiveTheChiSquareOfTheParameters) {
  // The gain of 2 parameters beyond 1 (the added effect) is chi2_2 exactly when the taus are
  // independent: c = 1, nu = 2.
  const Eigen::MatrixXd q = projector(smooth_columns(3)) - projector(smooth_columns(1));
  const ScaledChi2 m = satterthwaite(q, Eigen::MatrixXd::Identity(kTaus, kTaus));
  EXPECT_NEAR(m.c, 1.0, 1e-10);
  EXPECT_NEAR(m.nu, 2.0, 1e-10);
  EXPECT_EQ(satterthwaite(projector(Eigen::MatrixXd(kTaus, 0)), ar1_correlation(0.8)).nu, 0.0);
}

TEST(DiagnoseRevision, MatchHoldsItsLevelOnCorrelatedResiduals) {
  // u ~ N(0, R), R of lag-1 correlation 0.7; the gain u' Q u of two smooth directions beyond a
  // constant exceeds the matched c chi2_nu quantile at 5 % in 20000 draws 5.1 % of the time (the
  // binomial sd is 0.0015, and Satterthwaite's tail is itself approximate: within 0.01). One scale
  // for the whole curve, the rounds' P / n_eff with n_eff = P^2 / sum R_ij^2 (effective_taus_of),
  // gives 10.6 %, as the study's complete models found their levels wrong 10.5 % of the time:
  // a smooth change's gain spreads more than the whole curve's average says. (At 0.9 the whole
  // curve's scale errs the other way, 0.85 %; the match stays at 4.9 %.)
  const Eigen::MatrixXd r = ar1_correlation(0.7);
  const Eigen::MatrixXd q = projector(smooth_columns(3)) - projector(smooth_columns(1));
  const ScaledChi2 m = satterthwaite(q, r);
  ASSERT_GT(m.nu, 0.0);
  const double matched = m.c * kernels::chi2_quantile(0.95, m.nu);
  // P / n_eff with n_eff = P^2 / sum_ij R_ij^2: sum_ij R_ij^2 / P.
  const double global =
      r.cwiseAbs2().sum() / static_cast<double>(kTaus) * kernels::chi2_quantile(0.95, 2.0);
  const Eigen::MatrixXd l = r.llt().matrixL();
  std::mt19937_64 rng(20261128);
  std::normal_distribution<double> normal;
  constexpr int kDraws = 20000;
  int over_matched = 0, over_global = 0;
  for (int d = 0; d < kDraws; ++d) {
    Eigen::VectorXd z(kTaus);
    for (Eigen::Index i = 0; i < kTaus; ++i)
      z(i) = normal(rng);
    const Eigen::VectorXd u = l * z;
    const double gain = u.dot(q * u);
    over_matched += gain > matched ? 1 : 0;
    over_global += gain > global ? 1 : 0;
  }
  const double p_matched = static_cast<double>(over_matched) / kDraws;
  const double p_global = static_cast<double>(over_global) / kDraws;
  EXPECT_NEAR(p_matched, 0.05, 0.01);
  EXPECT_GT(p_global, 0.08) << "matched " << p_matched;
}

TEST(DiagnoseRevision, CompleteModelIsNotFoundWrong) {
  // The null study's seed 5: with the rounds' one scale its white and flicker levels, the truth,
  // were found wrong (one of 21 in 200 such records); with the match they are kept. A level given
  // 1.3 times too large is still found wrong (Diagnose.WrongCoefficientIsWrongNotIncomplete).
  const auto d = test::run_scenario(test::base_model(), test::base_model(), 1005, 0, 1);
  EXPECT_FALSE(d.coefficients_wrong);
  EXPECT_LT(d.revision_delta_ic, 0.0);
  EXPECT_EQ(d.model_after.terms, d.model_before.terms);
}

}  // namespace
}  // namespace allanlot
