// Chi-square distribution (regularized incomplete gamma and its inverse) and the edf
// algorithms: known values, closed forms and consistency between their branches.
#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace allanlot {
namespace {

using kernels::chi2_cdf;
using kernels::chi2_quantile;

// Reference quantiles from standard chi-square tables (e.g. Abramowitz & Stegun Table 26.8),
// given there to 6 significant digits.
TEST(Chi2, TableQuantiles) {
  struct Q {
    double p, dof, x;
  };
  const Q table[] = {{0.95, 1, 3.84146},   {0.05, 1, 0.00393214}, {0.975, 10, 20.4832},
                     {0.025, 10, 3.24697}, {0.99, 30, 50.8922},   {0.01, 30, 14.9535},
                     {0.5, 100, 99.3341}};
  for (const auto& q : table)
    EXPECT_NEAR(chi2_quantile(q.p, q.dof) / q.x, 1.0, 5e-6) << q.p << " " << q.dof;
}

// Closed forms: dof = 2 is exponential, F(x) = 1 - exp(-x/2); dof = 1 is a squared normal,
// F(x) = erf(sqrt(x/2)); dof = 3: F(x) = erf(sqrt(x/2)) - sqrt(2x/pi) exp(-x/2).
TEST(Chi2, ClosedForms) {
  for (const double p : {1e-12, 1e-6, 0.1585, 0.5, 0.8415, 0.999999}) {
    EXPECT_NEAR(chi2_quantile(p, 2.0) / (-2.0 * std::log1p(-p)), 1.0, 1e-12) << p;
  }
  for (const double x : {1e-8, 0.01, 0.5, 1.0, 4.0, 30.0}) {
    EXPECT_NEAR(chi2_cdf(x, 1.0), std::erf(std::sqrt(x / 2)), 1e-14) << x;
    EXPECT_NEAR(chi2_cdf(x, 3.0),
                std::erf(std::sqrt(x / 2)) - std::sqrt(2 * x / std::numbers::pi) * std::exp(-x / 2),
                1e-14)
        << x;
  }
  // One-sigma: P(|Z| < 1) = erf(1/sqrt 2) puts the chi-square(1) quantile at exactly 1.
  EXPECT_NEAR(chi2_quantile(std::erf(1.0 / std::sqrt(2.0)), 1.0), 1.0, 1e-12);
}

// Non-integer dof: the recurrence P(a + 1, x) = P(a, x) - x^a e^-x / Gamma(a + 1) ties the two
// branches (series / continued fraction) together, and quantile and cdf must invert each
// other, including tiny quantiles at dof < 1 and huge dof.
TEST(Chi2, NonIntegerDofConsistency) {
  for (const double a : {0.15, 0.7, 2.3, 7.9, 41.5}) {
    for (const double x : {0.05, 0.9, 3.0, a, a + 1.5, 2.0 * a + 10.0}) {
      const double lhs = kernels::gamma_p(a + 1.0, x);
      const double rhs =
          kernels::gamma_p(a, x) - std::exp(a * std::log(x) - x - std::lgamma(a + 1.0));
      EXPECT_NEAR(lhs, rhs, 2e-14) << a << " " << x;
      EXPECT_NEAR(kernels::gamma_p(a, x) + kernels::gamma_q(a, x), 1.0, 1e-14);
    }
  }
  // The exponent a ln x - x - ln Gamma(a) of the prefactor has magnitude ~dof, so its rounding
  // (~dof * eps, a few ulps more from ln Gamma) bounds the relative accuracy at large dof.
  for (const double dof : {0.05, 0.4, 1.0, 2.7, 9.55, 133.7, 4.2e4, 3e7}) {
    const double tol = 1e-10 + 1e-14 * dof;
    // At dof = 0.05 the 1e-9 quantile is ~1e-360, below the smallest double.
    for (const double p : {dof < 0.1 ? 1e-6 : 1e-9, 0.01, 0.1585, 0.5, 0.8415, 0.99, 1.0 - 1e-9}) {
      const double x = chi2_quantile(p, dof);
      ASSERT_TRUE(std::isfinite(x) && x > 0.0) << dof << " " << p;
      const double back = p <= 0.5 ? chi2_cdf(x, dof) : 1.0 - kernels::gamma_q(dof / 2, x / 2);
      EXPECT_NEAR(back / p, 1.0, tol) << dof << " " << p;
    }
  }
  // Wilson-Hilferty is accurate to ~1e-5 relative at dof = 3e4 (z = 1).
  const double dof = 3e4;
  const double wh = dof * std::pow(1.0 - 2.0 / (9 * dof) + std::sqrt(2.0 / (9 * dof)), 3);
  EXPECT_NEAR(chi2_quantile(0.841344746068543, dof) / wh, 1.0, 1e-5);
}

TEST(Chi2, DumbInputs) {
  for (const double p : {0.0, 1.0, -0.1, 1.1, std::nan("")})
    EXPECT_THROW(chi2_quantile(p, 3.0), std::invalid_argument) << p;
  for (const double dof : {0.0, -1.0, std::nan(""), HUGE_VAL})
    EXPECT_THROW(chi2_quantile(0.5, dof), std::invalid_argument) << dof;
  EXPECT_THROW(kernels::gamma_p(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(kernels::gamma_p(1.0, -1.0), std::invalid_argument);
  EXPECT_EQ(kernels::gamma_p(2.0, 0.0), 0.0);
  EXPECT_EQ(kernels::gamma_q(2.0, HUGE_VAL), 0.0);
}

// White PM in an overlapping Allan variance: the second differences of white phase at lag m
// have correlations -2/3 at lag m and 1/6 at lag 2m and none beyond, so for M terms
// 1/edf = (1/M) (1 + 2 (1 - m/M) 4/9 + 2 (1 - 2m/M) 1/36) = (35/18 - m/M) / M exactly, which
// is what Greenhall & Riley's case 4 (Table 2, a0 = 35/18, a1 = 1) must reproduce.
TEST(Edf, WhitePmOverlappingAllanIsExact) {
  const kernels::FiniteDifferenceKind oavar{2, true, false};
  for (const std::int64_t m : {2, 3, 10, 100}) {
    for (const std::int64_t n : {1001, 10001}) {
      const double M = static_cast<double>(kernels::greenhall_terms(oavar, m, n));
      ASSERT_EQ(M, static_cast<double>(n - 2 * m));
      const double exact = M / (35.0 / 18.0 - static_cast<double>(m) / M);
      EXPECT_NEAR(kernels::edf_greenhall(2, oavar, m, n) / exact, 1.0, 1e-12) << m << " " << n;
    }
  }
}

// The algorithm switches from the exact covariance sum (J <= 100) to the large-M asymptotes of
// Tables 1-2 and to the rescaled sum; around each switch the edf must be continuous. The
// paper's tables are fitted to ~1 %, but at the switch the unmodified filter also goes from
// F = m to the F -> infinity limit, which for OHVAR and white FM (m = 25 -> 26) moves the edf
// by 4.4 %: hence 5 %.
TEST(Edf, ContinuousAcrossAlgorithmBranches) {
  const kernels::FiniteDifferenceKind kinds[] = {
      {2, true, false}, {2, true, true}, {3, true, false}, {2, false, false}};
  for (const auto kind : kinds) {
    for (const int alpha : {1, 0, -1, -2}) {
      // Overlapping: J = min(M, (d+1) m) crosses 100 between m = 33 and 34 (d = 2) or 25 and
      // 26 (d = 3); non-overlapping: F switches to infinity at m (d+1) > 100.
      const std::int64_t m0 = kind.d == 2 ? 33 : 25;
      const double a = kernels::edf_greenhall(alpha, kind, m0, 100000);
      const double b = kernels::edf_greenhall(alpha, kind, m0 + 1, 100000);
      const double expected_ratio = static_cast<double>(100000 - (kind.d + 1) * (m0 + 1)) /
                                    static_cast<double>(100000 - (kind.d + 1) * m0);
      EXPECT_NEAR((b / a) * static_cast<double>(m0 + 1) / static_cast<double>(m0) /
                      (kind.overlapping ? expected_ratio : 1.0),
                  1.0, 0.05)
          << "d=" << kind.d << " ov=" << kind.overlapping << " mod=" << kind.modified
          << " alpha=" << alpha;
    }
  }
}

TEST(Edf, TotvarHoweCoefficients) {
  // SP1065 eq. (47): b T/tau - c with T/tau = (N - 1)/m.
  EXPECT_DOUBLE_EQ(kernels::edf_totvar(0, 4, 1001), 1.5 * 250);
  EXPECT_DOUBLE_EQ(kernels::edf_totvar(-1, 4, 1001), 1.17 * 250 - 0.22);
  EXPECT_DOUBLE_EQ(kernels::edf_totvar(-2, 4, 1001), 0.93 * 250 - 0.36);
  EXPECT_THROW(kernels::edf_totvar(-3, 4, 1001), std::invalid_argument);
}

TEST(Edf, DumbInputs) {
  const kernels::FiniteDifferenceKind avar{2, false, false};
  EXPECT_THROW(kernels::edf_greenhall(0, avar, 0, 100), std::invalid_argument);
  EXPECT_THROW(kernels::edf_greenhall(0, avar, 50, 100), std::invalid_argument);  // no term
  EXPECT_THROW(kernels::edf_greenhall(3, avar, 1, 100), std::invalid_argument);
  EXPECT_THROW(kernels::edf_greenhall(0, {4, false, false}, 1, 100), std::invalid_argument);
  EXPECT_THROW(kernels::edf_greenhall(-1, {1, false, false}, 1, 100), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot

namespace allanlot {
namespace {

// Reference values: scipy.stats.t.sf (two-sided, doubled) and scipy.special.betainc 1.10.
TEST(StudentT, TwoSidedTailMatchesReference) {
  const struct {
    double t, nu, p;
  } cases[] = {{2.228, 10, 0.05001177181711133}, {5, 30, 2.3296685467007786e-05},
               {7, 15, 4.280115581127817e-06},   {0.5, 3, 0.651447964848151},
               {10, 100, 9.901688984594094e-17}, {3, 1.5, 0.13354775425491328}};
  for (const auto& c : cases)
    EXPECT_NEAR(kernels::student_t_two_sided(c.t, c.nu), c.p, 1e-12 * c.p) << c.t << " " << c.nu;
  EXPECT_NEAR(kernels::beta_inc(2.5, 3.5, 0.7), 0.9228190654779194, 1e-14);
  EXPECT_NEAR(kernels::beta_inc(0.5, 0.5, 0.01), 0.06376856085851987, 1e-14);
  EXPECT_EQ(kernels::student_t_two_sided(0.0, 5.0), 1.0);
  EXPECT_THROW(kernels::beta_inc(0.0, 1.0, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
