// Honesty tests of the noise synthesis: every term and effect, alone and combined, has the
// Allan variance and PSD that its coefficient promises; the random numbers are Philox's; the
// output is byte-identical for any thread count.
//
// Statistical checks use z = ln(avar_meas / avar_model) / sqrt(2 / edf) per tau (for a
// chi-square variable with edf degrees of freedom, ln(chi2/edf) has sd ~ sqrt(2/edf)) and the
// gap sqrt(mean z^2) over an octave tau grid. The edf are SP1065's simple approximations for
// the overlapping Allan variance (Table 5, p. 38) for the noise type that dominates each tau.
// Neighbouring octave taus are positively correlated, so mean z^2 behaves like a chi-square
// with fewer than n_tau degrees of freedom divided by n_tau; even in the worst case (all z
// equal, 1 dof) P(gap > 3) = P(|z| > 3) = 0.27%, so kMaxGap = 3 fails a correct generator
// rarely, while every test also shows that a 10% error in the coefficient is detected.
#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/simulate/rng.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/spectral/fft.hpp"

#include <fftw3.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

namespace allanlot {
namespace {

using kernels::ChannelSpec;
using kernels::GaussMarkov;
using kernels::Sinusoid;

constexpr double kMaxGap = 3.0;
constexpr std::uint64_t kSeed = 20240917;

// Noise types by the exponent alpha of the rate PSD (S_y ~ f^alpha), for the edf.
enum class Noise { WhitePM = 2, WhiteFM = 0, FlickerFM = -1, RandomWalkFM = -2 };

// SP1065 Table 5 (p. 38): simple edf approximations for the overlapping Allan variance, with
// N the number of phase points.
double edf_simple(Noise type, double N, double m) {
  switch (type) {
  case Noise::WhitePM:
    return (N + 1) * (N - 2 * m) / (2 * (N - m));
  case Noise::WhiteFM:
    return (3 * (N - 1) / (2 * m) - 2 * (N - 2) / N) * 4 * m * m / (4 * m * m + 5);
  case Noise::FlickerFM:
    return m == 1 ? 2 * (N - 2) / (2.3 * N - 4.9) : 5 * N * N / (4 * m * (N + 3 * m));
  case Noise::RandomWalkFM:
    return (N - 2) / m * ((N - 1) * (N - 1) - 3 * m * (N - 1) + 4 * m * m) / ((N - 3) * (N - 3));
  }
  return 0;
}

std::vector<std::int64_t> octave_m(std::int64_t m_min, std::int64_t m_max) {
  std::vector<std::int64_t> ms;
  for (std::int64_t m = 1; m <= m_max; m *= 2)
    if (m >= m_min) ms.push_back(m);
  return ms;
}

struct GapResult {
  double gap = 0;
  std::vector<double> z;
};

// Gap between the OADEV of y and `expected(m)`, with the edf of `type(m)`.
GapResult gap(const std::vector<double>& y, double rate_hz, const std::vector<std::int64_t>& ms,
              const std::function<double(std::int64_t)>& expected,
              const std::function<Noise(std::int64_t)>& type) {
  const auto p = kernels::phase_from_rate(y, rate_hz, 0);
  const auto r = kernels::oadev(p, ms, 0);
  EXPECT_EQ(r.size(), ms.size());
  GapResult g;
  double sum = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double edf =
        edf_simple(type(r.m[i]), static_cast<double>(p.n_points()), static_cast<double>(r.m[i]));
    const double z = std::log(r.dev[i] * r.dev[i] / expected(r.m[i])) / std::sqrt(2 / edf);
    g.z.push_back(z);
    sum += z * z;
  }
  g.gap = std::sqrt(sum / static_cast<double>(r.size()));
  return g;
}

std::string describe(const GapResult& g) {
  std::string s = "gap " + std::to_string(g.gap) + ", z:";
  for (double z : g.z) {
    s += ' ';
    s += std::to_string(z);
  }
  return s;
}

std::vector<double> simulate(const ChannelSpec& spec, std::size_t n, std::uint64_t seed = kSeed,
                             std::uint64_t stream = 0, int nthreads = 0) {
  std::vector<double> y(n);
  kernels::simulate_channel(spec, seed, stream, y, nthreads);
  return y;
}

// One term alone: the measured gap against model_avar_sampled is small, and against the same
// model with the coefficient 10% too large it is not (the test has power).
void expect_term_matches(const ChannelSpec& spec, std::size_t n, std::int64_t m_min,
                         std::int64_t m_max, Noise type,
                         const std::function<void(ChannelSpec&)>& inflate) {
  const auto y = simulate(spec, n);
  const auto ms = octave_m(m_min, m_max);
  const auto model = [&](std::int64_t m) { return kernels::model_avar_sampled(spec, m); };
  const auto g = gap(y, spec.rate_hz, ms, model, [&](std::int64_t) { return type; });
  EXPECT_LT(g.gap, kMaxGap) << describe(g);
  std::printf("[ z-scores ] %s\n", describe(g).c_str());
  ChannelSpec wrong = spec;
  inflate(wrong);
  const auto bad = gap(
      y, spec.rate_hz, ms, [&](std::int64_t m) { return kernels::model_avar_sampled(wrong, m); },
      [&](std::int64_t) { return type; });
  EXPECT_GT(bad.gap, kMaxGap) << "a 10% coefficient error went unnoticed: " << describe(bad);
}

ChannelSpec with_rate(double rate_hz) {
  ChannelSpec s;
  s.rate_hz = rate_hz;
  return s;
}

// ---------------------------------------------------------------------------------------------
// Random numbers

TEST(Rng, PhiloxMatchesRandom123KnownAnswers) {
  // Random123's kat_vectors for philox4x32_10.
  using kernels::rng::philox4x32_10;
  EXPECT_EQ(philox4x32_10({0, 0, 0, 0}, {0, 0}),
            (kernels::rng::Counter{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}));
  EXPECT_EQ(
      philox4x32_10({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}, {0xffffffff, 0xffffffff}),
      (kernels::rng::Counter{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}));
  EXPECT_EQ(
      philox4x32_10({0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}, {0xa4093822, 0x299f31d0}),
      (kernels::rng::Counter{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}));
}

TEST(Rng, NormalsHaveUnitMomentsAndIndependentStreams) {
  // 2e5 deviates: the sample mean has sd 1/sqrt(n) = 0.0022, the variance sd sqrt(2/n) =
  // 0.0032, the kurtosis sd sqrt(24/n) = 0.011, the cross-correlation sd 0.0022: 5 sigma each.
  const std::size_t n = 200000;
  double s1 = 0, s2 = 0, s4 = 0, cross = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = kernels::rng::normal(1, 2, 3, i);
    const double b = kernels::rng::normal(1, 3, 3, i);  // another stream
    s1 += a;
    s2 += a * a;
    s4 += a * a * a * a;
    cross += a * b;
  }
  const double dn = static_cast<double>(n);
  EXPECT_NEAR(s1 / dn, 0.0, 5 * 0.0022);
  EXPECT_NEAR(s2 / dn, 1.0, 5 * 0.0032);
  EXPECT_NEAR(s4 / dn, 3.0, 5 * 0.011 * 3);
  EXPECT_NEAR(cross / dn, 0.0, 5 * 0.0022);
}

// ---------------------------------------------------------------------------------------------
// Flicker machinery

TEST(Flicker, KasdinFilterMatchesClosedForm) {
  // h_k = Gamma(k + 1/2) / (Gamma(1/2) k!). The recursion accumulates ~k ulps (1e-11 at
  // k = 1e5); the reference exp(lgamma - lgamma) loses eps * lgamma(1e5) ~ 3e-10.
  const auto h = kernels::kasdin_flicker_filter(100001);
  for (std::size_t k : {0ul, 1ul, 2ul, 10ul, 1000ul, 100000ul}) {
    const double kd = static_cast<double>(k);
    const double ref = std::exp(std::lgamma(kd + 0.5) - std::lgamma(0.5) - std::lgamma(kd + 1));
    EXPECT_NEAR(h[k] / ref, 1.0, 1e-9) << k;
  }
  EXPECT_DOUBLE_EQ(h[1], 0.5);
  EXPECT_DOUBLE_EQ(h[2], 0.375);
}

// The overlap-save convolution equals the direct sum B sum_j h_j g_{k-j} (long double), for
// the default single block and for many small blocks (n not a multiple of the block).
TEST(Flicker, OverlapSaveEqualsDirectConvolution) {
  const std::size_t n = 1537;
  ChannelSpec spec = with_rate(10);
  spec.terms.B = 0.7;
  const auto h = kernels::kasdin_flicker_filter(n);
  std::vector<long double> ref(n);
  const auto comp = static_cast<std::uint32_t>(kernels::rng::Component::Flicker);
  std::vector<double> g(n);
  for (std::size_t j = 0; j < n; ++j)
    g[j] = kernels::rng::normal(kSeed, 5, comp, j);
  for (std::size_t k = 0; k < n; ++k) {
    long double s = 0;
    for (std::size_t j = 0; j <= k; ++j)
      s += static_cast<long double>(h[j]) * g[k - j];
    ref[k] = 0.7L * s;
  }
  for (std::size_t block : {0ul, 100ul, 1ul}) {
    kernels::SimulationPlan plan(n, block);
    std::vector<double> y(n);
    plan.run(spec, kSeed, 5, y, 2);
    long double err = 0, norm = 0;
    for (std::size_t k = 0; k < n; ++k) {
      err += (y[k] - ref[k]) * (y[k] - ref[k]);
      norm += ref[k] * ref[k];
    }
    // FFT rounding: ~eps log2(P) relative in the L2 norm.
    EXPECT_LT(std::sqrt(static_cast<double>(err / norm)), 1e-13) << "block " << block;
  }
}

TEST(Flicker, DiscreteFactorKnownValues) {
  // I(1) = integral sin x = 1, I(2) = integral 4 sin x cos^4 x = 4/5 (simulate.hpp).
  EXPECT_NEAR(kernels::flicker_avar_factor(1), 1.0 / std::numbers::ln2, 1e-12);
  EXPECT_NEAR(kernels::flicker_avar_factor(2), 0.8 / std::numbers::ln2, 1e-12);
  double prev = kernels::flicker_avar_factor(1);
  for (std::int64_t m = 2; m <= 4096; m *= 2) {
    const double f = kernels::flicker_avar_factor(m);
    EXPECT_LT(f, prev) << m;
    EXPECT_GT(f, 1.0) << m;
    prev = f;
  }
  // The correction behaves as ((3/16) ln m + c) / (m^2 ln 2) (from 1/sin^3 x = 1/x^3 + 1/(2x)
  // + ...), so d(m) = (factor(m) - 1) m^2 ln 2 grows by (3/16) ln 2 = 0.130 per octave: a check
  // of the quadrature far from the exact small-m values.
  const auto d = [](std::int64_t m) {
    return (kernels::flicker_avar_factor(m) - 1) * static_cast<double>(m * m) * std::numbers::ln2;
  };
  EXPECT_NEAR(d(2048) - d(1024), 0.1875 * std::numbers::ln2, 0.005);
  EXPECT_LT(kernels::flicker_avar_factor(4096) - 1, 2e-7);
  EXPECT_LT(kernels::flicker_avar_factor(32) - 1, 2e-3);
  EXPECT_THROW(kernels::flicker_avar_factor(0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Each term alone: OADEV of simulated data vs the model.

TEST(SimulateAvar, WhiteRateNoise) {
  ChannelSpec s = with_rate(100);
  s.terms.N = 0.005;
  expect_term_matches(s, 1 << 18, 1, (1 << 18) / 32, Noise::WhiteFM,
                      [](ChannelSpec& w) { w.terms.N *= 1.1; });
}

TEST(SimulateAvar, FlickerIncludingDiscreteCorrection) {
  // From m = 2 (SP1065's m = 1 flicker edf is < 1); the small-m values test the discrete
  // correction flicker_avar_factor, the large-m ones the floor B^2 2 ln2 / pi; m <= n/64 keeps
  // the finite-record deficit (relative order m/n) well inside the uncertainty.
  ChannelSpec s = with_rate(1000);
  s.terms.B = 0.00125;
  expect_term_matches(s, 1 << 20, 2, (1 << 20) / 64, Noise::FlickerFM,
                      [](ChannelSpec& w) { w.terms.B *= 1.1; });
}

TEST(SimulateAvar, FlickerSmallMNeedsTheDiscreteCorrection) {
  // Without the correction, eq. (3)'s floor is far outside the uncertainty at m = 2..8.
  ChannelSpec s = with_rate(1000);
  s.terms.B = 0.00125;
  const auto y = simulate(s, 1 << 20);
  const auto continuous = gap(
      y, s.rate_hz, {2, 4, 8},
      [&](std::int64_t m) { return kernels::model_avar(s, static_cast<double>(m) / s.rate_hz); },
      [](std::int64_t) { return Noise::FlickerFM; });
  EXPECT_GT(continuous.gap, 10.0) << describe(continuous);
}

TEST(SimulateAvar, RateRandomWalk) {
  ChannelSpec s = with_rate(100);
  s.terms.K = 1e-3;
  expect_term_matches(s, 1 << 18, 1, (1 << 18) / 32, Noise::RandomWalkFM,
                      [](ChannelSpec& w) { w.terms.K *= 1.1; });
}

TEST(SimulateAvar, Quantization) {
  ChannelSpec s = with_rate(100);
  s.terms.Q = 2e-4;
  expect_term_matches(s, 1 << 18, 1, (1 << 18) / 32, Noise::WhitePM,
                      [](ChannelSpec& w) { w.terms.Q *= 1.1; });
}

TEST(SimulateAvar, GaussMarkovBothRegimes) {
  // tau_c = 0.5 s at 100 Hz: taus from 0.01 s (random-walk-like) to 82 s (white-like). The
  // random-walk edf is the smaller of the two regimes' edfs, hence conservative.
  ChannelSpec s = with_rate(100);
  s.markovs.push_back({0.01, 0.5});
  expect_term_matches(s, 1 << 18, 1, (1 << 18) / 32, Noise::RandomWalkFM,
                      [](ChannelSpec& w) { w.markovs[0].sigma *= 1.1; });
}

TEST(SimulateAvar, RampIsExact) {
  ChannelSpec s = with_rate(100);
  s.terms.R = 2e-3;
  s.offset = 9.80665;
  const auto y = simulate(s, 100000);
  const auto ms = octave_m(1, 100000 / 8);
  const auto r = kernels::oadev(kernels::phase_from_rate(y, s.rate_hz), ms);
  for (std::size_t i = 0; i < r.size(); ++i) {
    // Deterministic: only rounding of the stored phase (|x| <~ 1e3, eps 1e-13) against the
    // second difference R tau^2 >= 2e-7, averaged over >= 7.5e4 terms.
    const double model = kernels::model_avar(s, r.tau_s[i]);
    EXPECT_NEAR(r.dev[i] * r.dev[i] / model, 1.0, 1e-6) << "m=" << r.m[i];
  }
}

TEST(SimulateAvar, SinusoidWithinItsFiniteRecordBound) {
  // Deterministic: the overlapping estimator is the model times (1 - mean_i cos(2 theta_i))
  // over M = N - 2m equally spaced phases theta_i (step 2 pi f tau0), and
  // |mean cos| <= 1 / (M |sin(2 pi f tau0)|). Taus near the zeros of sin^4(pi f tau) are kept:
  // the bound is relative.
  ChannelSpec s = with_rate(100);
  s.sinusoids.push_back({0.02, 0.37, 0.3});
  const std::size_t n = 1 << 17;
  const auto y = simulate(s, n);
  const auto r = kernels::oadev(kernels::phase_from_rate(y, s.rate_hz), octave_m(1, n / 8));
  ASSERT_GT(r.size(), 10u);
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double model = kernels::model_avar(s, r.tau_s[i]);
    const double M = static_cast<double>(static_cast<std::int64_t>(n) + 1 - 2 * r.m[i]);
    const double bound = 1 / (M * std::abs(std::sin(2 * std::numbers::pi * 0.37 / 100)));
    EXPECT_NEAR(r.dev[i] * r.dev[i] / model, 1.0, bound + 1e-9) << "m=" << r.m[i];
  }
  // The point-sampled sinusoid (no sinc) would be off by 1/sinc^2(pi f tau0) - 1 = 4.5e-4 at
  // 0.37 Hz and 100 Hz: larger than the bound at small m, so the averaging matters.
}

// White + flicker + random walk at the paper's gyro X levels (Table: N = 18 deg/h/sqrt(Hz),
// B = 4.5 deg/h, K = 0.1 deg/h/sqrt(h), in deg/s units), 1 kHz, with the edf of the dominant
// term at each tau.
TEST(SimulateAvar, PaperGyroCombination) {
  ChannelSpec s = with_rate(1000);
  s.terms.N = 0.005;
  s.terms.B = 0.00125;
  s.terms.K = 0.1 / 216000;
  const std::size_t n = 1 << 20;
  const auto y = simulate(s, n);
  const auto dominant = [&](std::int64_t m) {
    const double tau = static_cast<double>(m) / s.rate_hz;
    const double white = s.terms.N * s.terms.N / tau;
    const double flicker =
        kernels::model_avar_sampled(s, m) - white - s.terms.K * s.terms.K * tau / 3;
    return white > flicker ? Noise::WhiteFM : Noise::FlickerFM;
  };
  const auto ms = octave_m(1, n / 64);
  const auto g = gap(
      y, s.rate_hz, ms, [&](std::int64_t m) { return kernels::model_avar_sampled(s, m); },
      dominant);
  EXPECT_LT(g.gap, kMaxGap) << describe(g);
  std::printf("[ z-scores ] %s\n", describe(g).c_str());
  // White noise dominates up to tau ~ 36 s, where the edf are large: a 10% error in N shows.
  ChannelSpec wrong = s;
  wrong.terms.N *= 1.1;
  const auto bad = gap(
      y, s.rate_hz, ms, [&](std::int64_t m) { return kernels::model_avar_sampled(wrong, m); },
      dominant);
  EXPECT_GT(bad.gap, kMaxGap) << describe(bad);
}

// ---------------------------------------------------------------------------------------------
// PSD: averaged periodogram vs model_psd_one_sided.

// One-sided PSD estimate averaged over K non-overlapping Hann-windowed segments of length L
// (mean removed per segment): 2 |X_j|^2 / (fs sum w^2) per segment. Each bin of a Gaussian
// process is then ~ S(f) chi2_{2K} / (2K).
std::vector<double> averaged_periodogram(const std::vector<double>& y, std::size_t L, double fs) {
  const std::size_t K = y.size() / L;
  std::vector<double> in(L), w(L), psd(L / 2 + 1, 0.0);
  std::vector<fftw_complex> out(L / 2 + 1);
  double w2 = 0;
  for (std::size_t i = 0; i < L; ++i) {
    w[i] = 0.5 -
           0.5 * std::cos(2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(L));
    w2 += w[i] * w[i];
  }
  fftw_plan plan;
  {
    std::lock_guard<std::mutex> lock(kernels::detail::fftw_planner_mutex());
    plan = fftw_plan_dft_r2c_1d(static_cast<int>(L), in.data(), out.data(), FFTW_ESTIMATE);
  }
  for (std::size_t k = 0; k < K; ++k) {
    double mean = 0;
    for (std::size_t i = 0; i < L; ++i)
      mean += y[k * L + i];
    mean /= static_cast<double>(L);
    for (std::size_t i = 0; i < L; ++i)
      in[i] = (y[k * L + i] - mean) * w[i];
    fftw_execute(plan);
    for (std::size_t j = 0; j < out.size(); ++j)
      psd[j] +=
          2 * (out[j][0] * out[j][0] + out[j][1] * out[j][1]) / (fs * w2) / static_cast<double>(K);
  }
  {
    std::lock_guard<std::mutex> lock(kernels::detail::fftw_planner_mutex());
    fftw_destroy_plan(plan);
  }
  return psd;
}

// Wilson & Hilferty (1931) quantile of chi2_nu / nu: (1 - 2/(9nu) + z sqrt(2/(9nu)))^3,
// accurate to ~1e-3 for nu >= 100.
double chi2_over_nu_quantile(double nu, double z) {
  const double a = 2 / (9 * nu);
  return std::pow(1 - a + z * std::sqrt(a), 3);
}

struct PsdCase {
  const char* name;
  ChannelSpec spec;
};

class SimulatePsd : public ::testing::TestWithParam<PsdCase> {};

// Bins 16 .. L/40: above 16 bins the Hann main lobe's curvature bias on a 1/f^2 spectrum is
// < 1%; below fs/40 the continuous-time forms differ from the sampled spectra by < 0.7%
// (quantization's sinc^2, random walk's sinc^2 and aliases, flicker's 1/(2 sin)). Checks: the
// number of bins outside the two-sided 99% chi-square band is at most 3x the expected 1% plus
// 4 (binomial tail < 1e-4), and the mean ratio estimate/model over the bins is within 3% (the
// mean of ~390 bins of sd 1/sqrt(K) = 0.125 has sd ~0.006-0.009 with Hann's neighbour
// correlation, plus the < 1% biases).
TEST_P(SimulatePsd, PeriodogramWithinChiSquareBand) {
  const auto& spec = GetParam().spec;
  const std::size_t n = 1 << 20, L = 1 << 14;
  const auto y = simulate(spec, n);
  const auto psd = averaged_periodogram(y, L, spec.rate_hz);
  const double nu = 2.0 * static_cast<double>(n / L);
  const double lo = chi2_over_nu_quantile(nu, -2.5758), hi = chi2_over_nu_quantile(nu, 2.5758);
  std::size_t outside = 0, bins = 0;
  double sum_ratio = 0;
  for (std::size_t j = 16; j <= L / 40; ++j) {
    const double f = static_cast<double>(j) * spec.rate_hz / static_cast<double>(L);
    const double r = psd[j] / kernels::model_psd_one_sided(spec, f);
    outside += (r < lo || r > hi) ? 1 : 0;
    sum_ratio += r;
    ++bins;
  }
  const double mean_ratio = sum_ratio / static_cast<double>(bins);
  std::printf("[ psd      ] %s: mean ratio %.4f, %zu of %zu bins outside the 99%% band\n",
              GetParam().name, mean_ratio, outside, bins);
  EXPECT_LE(outside, static_cast<std::size_t>(0.03 * static_cast<double>(bins)) + 4);
  EXPECT_NEAR(mean_ratio, 1.0, 0.03);
}

ChannelSpec psd_spec(double N, double B, double K, double Q, double sigma_gm, double tau_gm) {
  ChannelSpec s = with_rate(100);
  s.terms = {0, K, B, N, Q};
  if (sigma_gm > 0) s.markovs.push_back({sigma_gm, tau_gm});
  return s;
}

INSTANTIATE_TEST_SUITE_P(Terms, SimulatePsd,
                         ::testing::Values(PsdCase{"white", psd_spec(0.005, 0, 0, 0, 0, 0)},
                                           PsdCase{"flicker", psd_spec(0, 0.00125, 0, 0, 0, 0)},
                                           PsdCase{"random_walk", psd_spec(0, 0, 1e-3, 0, 0, 0)},
                                           PsdCase{"quantization", psd_spec(0, 0, 0, 2e-4, 0, 0)},
                                           PsdCase{"markov", psd_spec(0, 0, 0, 0, 0.01, 0.2)},
                                           PsdCase{"combination",
                                                   psd_spec(0.002, 0.002, 5e-4, 5e-5, 0.003, 0.1)}),
                         [](const auto& p) { return std::string(p.param.name); });

// ---------------------------------------------------------------------------------------------
// Reproducibility

ChannelSpec everything() {
  ChannelSpec s = with_rate(250);
  s.terms = {1e-4, 1e-3, 2e-3, 5e-3, 1e-5};
  s.sinusoids.push_back({0.01, 1.7, 0.4});
  s.markovs.push_back({0.004, 0.3});
  s.markovs.push_back({0.002, 0.001});  // tau_c << tau0: carries vanish within a few samples
  s.offset = 9.80665;
  return s;
}

TEST(SimulateReproducible, SameBytesForOneTwoSevenThreads) {
  // n spans several generation blocks and ends in a partial one.
  const std::size_t n = 100003;
  const auto spec = everything();
  const auto y1 = simulate(spec, n, kSeed, 3, 1);
  const auto y2 = simulate(spec, n, kSeed, 3, 2);
  const auto y7 = simulate(spec, n, kSeed, 3, 7);
  EXPECT_EQ(std::memcmp(y1.data(), y2.data(), n * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(y1.data(), y7.data(), n * sizeof(double)), 0);
  // A reused plan (filter spectrum cached) gives the same bytes as a fresh one.
  kernels::SimulationPlan plan(n);
  std::vector<double> a(n), b(n);
  plan.run(spec, kSeed, 3, a, 2);
  plan.run(spec, kSeed, 3, b, 1);
  EXPECT_EQ(std::memcmp(a.data(), y1.data(), n * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(b.data(), y1.data(), n * sizeof(double)), 0);
}

TEST(SimulateReproducible, SeedsAndStreamsDiffer) {
  const std::size_t n = 4096;
  const auto spec = everything();
  const auto base = simulate(spec, n, kSeed, 0);
  const auto other_seed = simulate(spec, n, kSeed + 1, 0);
  const auto other_stream = simulate(spec, n, kSeed, 1);
  std::size_t same_seed = 0, same_stream = 0;
  for (std::size_t i = 0; i < n; ++i) {
    same_seed += base[i] == other_seed[i] ? 1 : 0;
    same_stream += base[i] == other_stream[i] ? 1 : 0;
  }
  EXPECT_EQ(same_seed, 0u);
  EXPECT_EQ(same_stream, 0u);
}

TEST(SimulateReproducible, AddingATermLeavesTheOthersUnchanged) {
  // Each component draws from its own sequence, so white + flicker - flicker == white.
  const std::size_t n = 5000;
  ChannelSpec white = with_rate(100);
  white.terms.N = 0.01;
  ChannelSpec flicker = with_rate(100);
  flicker.terms.B = 0.02;
  ChannelSpec both = white;
  both.terms.B = 0.02;
  const auto yw = simulate(white, n), yf = simulate(flicker, n), yb = simulate(both, n);
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_NEAR(yb[i], yw[i] + yf[i], 1e-15) << i;
}

// ---------------------------------------------------------------------------------------------
// Theory and dumb inputs

TEST(SimulateModel, AvarTermsAndLimits) {
  ChannelSpec s = with_rate(1000);
  s.terms = {2.0, 3.0, 5.0, 7.0, 11.0};
  const double tau = 0.37;
  const double expected = 4 * tau * tau / 2 + 9 * tau / 3 +
                          25 * 2 * std::numbers::ln2 / std::numbers::pi + 49 / tau +
                          3 * 121 / (tau * tau);
  EXPECT_NEAR(kernels::model_avar(s, tau) / expected, 1.0, 1e-14);
  // Gauss-Markov: K^2 tau/3 with K^2 = 2 sigma^2/tau_c for tau << tau_c (series branch),
  // N^2/tau with N^2 = 2 sigma^2 tau_c for tau >> tau_c (closed-form branch).
  ChannelSpec gm = with_rate(1000);
  gm.markovs.push_back({0.5, 10.0});
  EXPECT_NEAR(kernels::model_avar(gm, 1e-4) / (2 * 0.25 / 10 * 1e-4 / 3), 1.0, 1e-4);
  EXPECT_NEAR(kernels::model_avar(gm, 1e6) / (2 * 0.25 * 10 / 1e6), 1.0, 2e-5);
  // The two branches of u(a) meet continuously at a = 0.5.
  EXPECT_NEAR(kernels::model_avar(gm, 5.0 * (1 - 1e-12)) / kernels::model_avar(gm, 5.0), 1.0,
              1e-10);
}

TEST(SimulateModel, PsdForms) {
  ChannelSpec s = with_rate(1000);
  s.terms.N = 0.005;
  EXPECT_DOUBLE_EQ(kernels::model_psd_one_sided(s, 3.0), 2 * 0.005 * 0.005);  // docs/formats.md
  ChannelSpec b = with_rate(1000);
  b.terms.B = 0.1;
  EXPECT_NEAR(kernels::model_psd_one_sided(b, 2.0), 0.01 / (std::numbers::pi * 2.0), 1e-18);
}

TEST(SimulateDumbInputs, RejectedWithTheFieldName) {
  const auto expect_throw = [](ChannelSpec s, const std::string& field) {
    std::vector<double> y(16);
    try {
      kernels::simulate_channel(s, 1, 0, y);
      ADD_FAILURE() << "no exception for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  ChannelSpec s = with_rate(100);
  s.rate_hz = 0;
  expect_throw(s, "rate_hz");
  s = with_rate(100);
  s.terms.N = -1;
  expect_throw(s, "N");
  s = with_rate(100);
  s.terms.B = std::nan("");
  expect_throw(s, "B");
  s = with_rate(100);
  s.sinusoids.push_back({1, 60, 0});
  expect_throw(s, "frequency_hz");
  s = with_rate(100);
  s.markovs.push_back({1, 0});
  expect_throw(s, "tau_c_s");
  s = with_rate(100);
  s.offset = INFINITY;
  expect_throw(s, "offset");
  std::vector<double> empty;
  EXPECT_THROW(kernels::simulate_channel(with_rate(1), 1, 0, empty), std::invalid_argument);
  kernels::SimulationPlan plan(10);
  std::vector<double> wrong(11);
  EXPECT_THROW(plan.run(with_rate(1), 1, 0, wrong), std::invalid_argument);
  // n = 1 and n = 2 work, flicker included.
  for (std::size_t n : {1ul, 2ul}) {
    ChannelSpec all = everything();
    std::vector<double> y(n);
    kernels::simulate_channel(all, 1, 0, y);
    for (double v : y)
      EXPECT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace allanlot
