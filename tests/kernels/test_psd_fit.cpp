// The PSD-domain eq. (3) fit (kernels/model/psd_fit.hpp) and its comparison with the Allan fit.
//
// Three kinds of check, as for every estimator here:
//  - exactness of the expected Welch value of each term: against its closed-form PSD where
//    the window cannot matter (mid band), and against the Welch estimator run on a signal
//    whose periodogram is deterministic (a pure ramp);
//  - theory on simulated noise: the Welch average of pure random walk / flicker against the
//    expected value, with a tolerance from the chi-square edf of the pooled bins;
//  - recovery of the paper's coefficients (N within 10 % is the bar; the tolerance
//    used is 3 sigma of the fit's own uncertainty, far tighter) and agreement with the Allan fit.
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/model/psd_fit.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/spectral/psd.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace allanlot {
namespace {

using kernels::Term;
constexpr double kPi = std::numbers::pi;
constexpr auto kR = static_cast<std::size_t>(Term::R);
constexpr auto kK = static_cast<std::size_t>(Term::K);
constexpr auto kB = static_cast<std::size_t>(Term::B);
constexpr auto kN = static_cast<std::size_t>(Term::N);
constexpr auto kQ = static_cast<std::size_t>(Term::Q);

std::vector<double> simulate(const kernels::ChannelSpec& spec, std::size_t n, std::uint64_t seed) {
  std::vector<double> y(n);
  kernels::simulate_channel(spec, seed, 0, y, 0);
  return y;
}

TEST(WelchTermPsd, MatchesClosedFormsInMidBand) {
  const std::int64_t L = 4096;
  const double fs = 100.0, tau0 = 1.0 / fs;
  const auto g = kernels::welch_term_psd(L, fs);
  ASSERT_EQ(g[kN].size(), static_cast<std::size_t>(L / 2 + 1));
  EXPECT_TRUE(std::isnan(g[kN][0]) && std::isnan(g[kN][1]));
  for (std::int64_t k : {8, 40, 200, 1000, 2047}) {
    const auto ks = static_cast<std::size_t>(k);
    const double f = static_cast<double>(k) * fs / static_cast<double>(L);
    SCOPED_TRACE(k);
    // White: one-sided 2 N^2 exactly (docs/formats.md).
    EXPECT_NEAR(g[kN][ks], 2.0, 1e-12);
    // Quantization: the window averages 8 sin^2(pi f tau0) / tau0 over its main lobe (a few
    // bins), so the relative error is of the order of the curvature, (pi / L)^2 times the
    // second derivative of sin^2 over sin^2, <= 2 (pi / L)^2 / sin^2(pi k / L).
    const double q = 8.0 * std::pow(std::sin(kPi * f * tau0), 2) / tau0;
    const double h = kPi / static_cast<double>(L);
    EXPECT_NEAR(g[kQ][ks] / q, 1.0,
                2.0 * h * h / std::pow(std::sin(h * static_cast<double>(k)), 2));
    if (k > 400) continue;
    // Flicker and random walk: 1/(pi f) and 1/(2 pi^2 f^2), up to the window's smoothing of
    // the curvature (relative ~ c / k^2 with c <= 1 for Hann) and the interval-mean / aliasing
    // factors, which stay below 1 % for f <= fs / 10.
    const double tol = 1.0 / static_cast<double>(k * k) + 0.01;
    EXPECT_NEAR(g[kB][ks] * kPi * f, 1.0, tol);
    EXPECT_NEAR(g[kK][ks] * 2.0 * kPi * kPi * f * f, 1.0, tol);
  }
}

TEST(WelchTermPsd, RampIsExactAgainstTheEstimator) {
  // A pure ramp's periodogram is the same in every segment: the Welch result must equal the
  // expected value to rounding at every bin k >= 2.
  const std::int64_t n = 1 << 14;
  const double fs = 50.0, R = 3e-3;
  std::vector<double> y(static_cast<std::size_t>(n));
  for (std::int64_t i = 0; i < n; ++i)
    y[static_cast<std::size_t>(i)] = R * (static_cast<double>(i) + 0.5) / fs;
  const kernels::PsdResult p = kernels::welch_psd(y, fs, 1);
  const auto g = kernels::welch_term_psd(p.segment_length, fs);
  for (std::size_t k = 2; k < p.size(); ++k)
    EXPECT_NEAR(p.psd[k], R * R * g[kR][k], 1e-9 * R * R * g[kR][2]) << k;
}

// Pooled over many bins, the ratio Welch / expected of a pure term has mean 1 and sd
// sqrt(2 / nu_pooled); 4 sd allows for the bins' residual correlation (neighbours share 4/9).
void expect_term_matches(const kernels::ChannelSpec& spec, std::size_t term, double theta,
                         std::int64_t k_lo, std::int64_t k_hi) {
  const std::size_t n = 1 << 20;
  const auto y = simulate(spec, n, 7);
  const kernels::PsdResult p = kernels::welch_psd(y, spec.rate_hz, 0);
  const auto g = kernels::welch_term_psd(p.segment_length, spec.rate_hz);
  double sum = 0, nu = 0;
  int cnt = 0;
  for (std::int64_t k = k_lo; k <= k_hi; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    sum += p.psd[ks] / (theta * g[term][ks]);
    nu += p.edf[ks];
    ++cnt;
  }
  const double mean = sum / cnt;
  EXPECT_NEAR(mean, 1.0, 4.0 * std::sqrt(2.0 / nu) * std::sqrt(1.0 + 2.0 * 4.0 / 9.0));
}

TEST(WelchTermPsd, RandomWalkMatchesSimulationAtLowBins) {
  kernels::ChannelSpec s;
  s.rate_hz = 100;
  s.terms.K = 1e-3;
  // The low bins are where the window's smoothing of 1/f^2 matters most (k = 2..6).
  expect_term_matches(s, kK, s.terms.K * s.terms.K, 2, 6);
  expect_term_matches(s, kK, s.terms.K * s.terms.K, 7, 200);
}

TEST(WelchTermPsd, FlickerMatchesSimulationAtLowBins) {
  kernels::ChannelSpec s;
  s.rate_hz = 100;
  s.terms.B = 1e-3;
  expect_term_matches(s, kB, s.terms.B * s.terms.B, 2, 6);
  expect_term_matches(s, kB, s.terms.B * s.terms.B, 7, 400);
}

// The paper's gyro X (its Table; units deg/s and s, docs/formats.md) on 2^21 samples.
kernels::ChannelSpec gyro() {
  kernels::ChannelSpec s;
  s.rate_hz = 1000;
  s.terms.N = 0.005;
  s.terms.B = 0.00125;
  s.terms.K = 4.63e-7;
  return s;
}

TEST(PsdFit, RecoversTheWhiteNoiseCoefficientAndAgreesWithTheAllanFit) {
  const auto spec = gyro();
  const std::size_t n = std::size_t{1} << 21;
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    SCOPED_TRACE(seed);
    const auto y = simulate(spec, n, seed);
    const kernels::PsdResult p = kernels::welch_psd(y, spec.rate_hz, 0);
    const kernels::PsdFitResult f = kernels::psd_fit(p);
    ASSERT_EQ(f.status, kernels::FitStatus::Ok);
    const auto& tn = f[Term::N];
    ASSERT_TRUE(tn.detected);
    // The bar: within 10 %. The fit's own 1-sigma is ~0.1 % here; 4 sigma.
    EXPECT_NEAR(tn.value, spec.terms.N, 0.1 * spec.terms.N);
    EXPECT_NEAR(tn.value, spec.terms.N, 4.0 * tn.sigma);
    // Flicker is at the low edge of what 16 segments of 35 min see; whatever the fit says must
    // cover the truth within 4 sigma (or its upper bound must).
    const auto& tb = f[Term::B];
    if (tb.detected)
      EXPECT_NEAR(tb.value, spec.terms.B, 4.0 * tb.sigma);
    else
      EXPECT_GE(tb.upper, spec.terms.B * 0.5);
    // A good fit: chi2/dof near 1 (P ~ 50 bins: sd sqrt(2/45) = 0.21; 1 +- 4 sd).
    EXPECT_GT(f.chi2_dof, 0.2);
    EXPECT_LT(f.chi2_dof, 1.9);

    // The Allan-domain fit of the same data agrees term by term.
    const auto ph = kernels::make_phase(y, kernels::DataType::Rate, spec.rate_hz, 0);
    const auto m =
        kernels::make_m_list(kernels::parse_tau_grid("log:8"),
                             kernels::max_m(kernels::Stat::Oadev, ph.n_points()), ph.n_points());
    kernels::StatResult oadev = kernels::compute(kernels::Stat::Oadev, ph, m, 0);
    kernels::add_confidence(kernels::Stat::Oadev, ph, oadev, 0.683, 0);
    kernels::Eq3Fit eq3;
    const kernels::FitResult a = eq3.fit(oadev, ph.tau0_s, static_cast<std::int64_t>(n));
    const kernels::FitAgreement g = kernels::compare_fits(a.terms, f.terms);
    EXPECT_TRUE(g.agree) << "max |z| " << g.max_abs_z << " on term " << g.worst_term;
  }
}

TEST(PsdFit, DisagreementIsFlaggedWhenTheFitsDiffer) {
  // compare_fits must be able to fail: a fit whose N is off by 10 sigma.
  std::array<kernels::TermFit, kernels::kNumTerms> a{}, b{};
  a[kN].theta = a[kN].theta_free = 1.0;
  a[kN].theta_sigma = 0.01;
  b[kN] = a[kN];
  b[kN].theta = b[kN].theta_free = 1.0 + 10 * std::hypot(0.01, 0.01);
  const auto g = kernels::compare_fits(a, b);
  EXPECT_FALSE(g.agree);
  EXPECT_EQ(g.worst_term, static_cast<int>(kN));
  EXPECT_NEAR(g.max_abs_z, 10.0, 1e-9);
  EXPECT_TRUE(kernels::compare_fits(a, a).agree);
}

TEST(PsdFit, QuantizationAndWhiteSeparate) {
  // Q shows in the PSD as the f^2 rise towards Nyquist: N = 0.01 u s^0.5, Q = 1e-4 u s at
  // 1 kHz make them equal at 8 Q^2 sin^2(pi f tau0) / tau0 = 2 N^2, f ~ 160 Hz.
  kernels::ChannelSpec s;
  s.rate_hz = 1000;
  s.terms.N = 0.01;
  s.terms.Q = 1e-4;
  const auto y = simulate(s, std::size_t{1} << 20, 3);
  const kernels::PsdResult p = kernels::welch_psd(y, s.rate_hz, 0);
  const kernels::PsdFitResult f = kernels::psd_fit(p);
  ASSERT_EQ(f.status, kernels::FitStatus::Ok);
  ASSERT_TRUE(f[Term::Q].detected);
  EXPECT_NEAR(f[Term::Q].value, s.terms.Q, 4.0 * f[Term::Q].sigma);
  EXPECT_NEAR(f[Term::N].value, s.terms.N, 4.0 * f[Term::N].sigma);
  EXPECT_FALSE(f[Term::K].detected);
  EXPECT_FALSE(f[Term::R].detected);
}

// The regressors kept from channel to channel (WelchTermCache) give the fit without them, bit
// for bit, also when the segment length changes between two channels and back.
TEST(PsdFit, CachedRegressorsChangeNothing) {
  kernels::ChannelSpec s;
  s.rate_hz = 1000;
  s.terms.N = 0.01;
  s.terms.B = 0.002;
  const auto long_y = simulate(s, std::size_t{1} << 20, 5);
  const auto short_y = simulate(s, std::size_t{1} << 18, 6);
  const kernels::PsdResult a = kernels::welch_psd(long_y, s.rate_hz, 1);
  const kernels::PsdResult b = kernels::welch_psd(short_y, s.rate_hz, 1);
  ASSERT_NE(a.segment_length, b.segment_length);
  kernels::WelchTermCache cache;
  for (const kernels::PsdResult* p : {&a, &b, &a}) {
    const kernels::PsdFitResult plain = kernels::psd_fit(*p);
    const kernels::PsdFitResult cached = kernels::psd_fit(*p, {}, &cache);
    ASSERT_EQ(plain.status, cached.status);
    for (std::size_t t = 0; t < kernels::kNumTerms; ++t) {
      EXPECT_EQ(plain.terms[t].value, cached.terms[t].value) << t;
      EXPECT_EQ(plain.terms[t].sigma, cached.terms[t].sigma) << t;
    }
    EXPECT_EQ(plain.psd_model, cached.psd_model);
  }
}

// The regressors' four parts run as OpenMP tasks: the same bits at 1, 2 and 4 threads.
TEST(WelchTermPsd, SameBitsForAnyThreadCount) {
  const auto one = kernels::welch_term_psd(std::int64_t{1} << 14, 250.0, 1);
  for (const int threads : {2, 4}) {
    const auto more = kernels::welch_term_psd(std::int64_t{1} << 14, 250.0, threads);
    for (std::size_t t = 0; t < kernels::kNumTerms; ++t)
      for (std::size_t k = 2; k < one[t].size(); ++k)
        ASSERT_EQ(one[t][k], more[t][k]) << "term " << t << " bin " << k << ", " << threads;
  }
}

TEST(PsdFit, DumbInputs) {
  kernels::PsdResult p;
  EXPECT_THROW(kernels::psd_fit(p), std::invalid_argument);
  EXPECT_THROW(kernels::welch_term_psd(15, 1.0), std::invalid_argument);
  EXPECT_THROW(kernels::welch_term_psd(64, 0.0), std::invalid_argument);
  kernels::PsdFitOptions o;
  o.first_bin = 1;
  std::vector<double> y(4096, 0.0);
  y[7] = 1.0;
  const auto q = kernels::welch_psd(y, 10.0, 1);
  EXPECT_THROW(kernels::psd_fit(q, o), std::invalid_argument);
  // An all-zero record: no data to fit, not a crash.
  const auto z = kernels::welch_psd(std::vector<double>(4096, 0.0), 10.0, 1);
  EXPECT_EQ(kernels::psd_fit(z).status, kernels::FitStatus::NoData);
}

}  // namespace
}  // namespace allanlot
