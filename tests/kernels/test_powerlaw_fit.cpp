// The power-law model of clocks (kernels/powerlaw, docs/clocks.md): its theory against NIST
// SP1065's power-law relations, and the fit against clocks simulated by a generator written
// here, independent of kernels/simulate: white FM as white samples, flicker FM and flicker PM by
// Kasdin's fractional-difference filter (Kasdin 1995, Proc. IEEE 83(5), eq. (115): h_0 = 1,
// h_k = h_{k-1} (k - 1/2) / k) applied by a radix-2 FFT of this file, random-walk FM as the
// running sum of white samples, white PM as white phase.
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/powerlaw/fit.hpp"
#include "kernels/powerlaw/names.hpp"
#include "kernels/powerlaw/theory.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

namespace {

namespace pl = allanlot::kernels::powerlaw;
namespace k = allanlot::kernels;
constexpr double kPi = std::numbers::pi;

TEST(PowerLawNames, OneNamePerAlpha) {
  EXPECT_EQ(pl::noise_type_name(2), "white PM");
  EXPECT_EQ(pl::noise_type_name(1), "flicker PM");
  EXPECT_EQ(pl::noise_type_name(0), "white FM");
  EXPECT_EQ(pl::noise_type_name(-1), "flicker FM");
  EXPECT_EQ(pl::noise_type_name(-2), "random-walk FM");
  EXPECT_EQ(pl::noise_type_name(3), "");
  EXPECT_EQ(pl::noise_type_name_long(-4), "random run FM");
  EXPECT_THROW(pl::level_index(-3), std::invalid_argument);
}

// SP1065 sec. 5.2.4 (p. 38) and Table 5: AVAR of white FM h0 / (2 tau), flicker FM 2 ln2 h-1,
// random-walk FM (2 pi^2 / 3) h-2 tau, white PM 3 f_h h2 / (4 pi^2 tau^2); and the MVAR / AVAR
// ratios R(n) of sec. 5.2.5 (p. 39): 1/n for white PM, 1/2, 0.675 and 0.825 for white, flicker
// and random-walk FM at large n.
TEST(PowerLawTheory, AvarAndMvarAreSp1065s) {
  const double tau0 = 0.5, tau = 64.0;
  EXPECT_DOUBLE_EQ(pl::avar_per_h(0, tau, tau0), 1.0 / (2.0 * tau));
  EXPECT_DOUBLE_EQ(pl::avar_per_h(-1, tau, tau0), 2.0 * std::log(2.0));
  EXPECT_DOUBLE_EQ(pl::avar_per_h(-2, tau, tau0), 2.0 * kPi * kPi / 3.0 * tau);
  EXPECT_DOUBLE_EQ(pl::avar_per_h(2, tau, tau0),
                   3.0 * (1.0 / (2 * tau0)) / (4 * kPi * kPi * tau * tau));
  EXPECT_NEAR(pl::mvar_per_h(2, tau, tau0) / pl::avar_per_h(2, tau, tau0), tau0 / tau, 1e-15);
  EXPECT_NEAR(pl::mvar_per_h(-1, tau, tau0) / pl::avar_per_h(-1, tau, tau0), 0.675, 1e-3);
  EXPECT_NEAR(pl::mvar_per_h(-2, tau, tau0) / pl::avar_per_h(-2, tau, tau0), 0.825, 1e-3);
  // White FM's exact MVAR: equal to AVAR at m = 1, R(n) -> 1/2 as n grows (within 1/n^2).
  EXPECT_DOUBLE_EQ(pl::mvar_per_h(0, tau0, tau0), pl::avar_per_h(0, tau0, tau0));
  EXPECT_NEAR(pl::mvar_per_h(0, 1024 * tau0, tau0) / pl::avar_per_h(0, 1024 * tau0, tau0), 0.5,
              1e-5);
  EXPECT_THROW(pl::avar_per_h(3, tau, tau0), std::invalid_argument);
  EXPECT_THROW(pl::mvar_per_h(0, tau, 0.0), std::invalid_argument);
}

// In-place iterative radix-2 FFT (n a power of two); sign -1 forward, +1 inverse (unscaled).
void fft(std::vector<std::complex<double>>& a, int sign) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1)
      j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double ang = sign * 2.0 * kPi / static_cast<double>(len);
    const std::complex<double> wl(std::cos(ang), std::sin(ang));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1.0);
      for (std::size_t j = 0; j < len / 2; ++j) {
        const auto u = a[i + j], v = a[i + j + len / 2] * w;
        a[i + j] = u + v;
        a[i + j + len / 2] = u - v;
        w *= wl;
      }
    }
  }
}

// Kasdin's flicker sequence of n samples: white w of variance q filtered by (1 - z^-1)^(-1/2).
// Its two-sided PSD is q tau0 / (2 sin(pi f tau0)) -> q / (2 pi f), one-sided q / (pi f): a
// level h_-1 = q / pi in the quantity filtered.
std::vector<double> kasdin_flicker(std::size_t n, double q, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, std::sqrt(q));
  std::size_t len = 1;
  while (len < 2 * n)
    len <<= 1;
  std::vector<std::complex<double>> h(len), w(len);
  double hk = 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    h[i] = hk;
    hk *= (static_cast<double>(i) + 0.5) / static_cast<double>(i + 1);
    w[i] = g(rng);
  }
  fft(h, -1);
  fft(w, -1);
  for (std::size_t i = 0; i < len; ++i)
    w[i] *= h[i];
  fft(w, +1);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = w[i].real() / static_cast<double>(len);
  return out;
}

struct Truth {
  double h2 = 0, h1 = 0, h0 = 0, hm1 = 0, hm2 = 0;
};

// Fractional frequency y at tau0 = 1 s of the levels in `t` (white PM and flicker PM through the
// phase x, y_k = x_{k+1} - x_k). Flicker FM is drawn at 4 times the rate and averaged over each
// sample, as a counter averages a continuous frequency: Kasdin's discrete sequence exceeds the
// continuous flicker floor at m = 1 by 44 % (the part above 1/f near its Nyquist frequency), which
// would read as white FM; at m = 4 sub-samples the excess is a few per cent of a small share. A
// discrete random walk of step variance q has AVAR q (2 m^2 + 1) / (6 m) at m (the continuous
// (2 pi^2 / 3) h-2 tau with h-2 = q / (2 pi^2), plus q / (6 m), which is white FM of level q / 3):
// that white FM is added to the returned truth.
std::vector<double> clock(std::size_t n, Truth& t, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n, 0.0), x(n + 1, 0.0);
  const double q_rw = 2.0 * kPi * kPi * t.hm2;
  double walk = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    walk += std::sqrt(q_rw) * g(rng);
    y[i] = std::sqrt(t.h0 / 2.0) * g(rng) + walk;
  }
  if (t.hm1 > 0) {
    // At tau0 / 4 the same one-sided level h-1 needs the driving variance pi h-1 (it does not
    // depend on the rate: q tau0' / (2 pi f tau0') per unit of two-sided density).
    constexpr std::size_t kOver = 4;
    const auto f = kasdin_flicker(kOver * n, kPi * t.hm1, rng);
    for (std::size_t i = 0; i < n; ++i) {
      double sum = 0.0;
      for (std::size_t j = 0; j < kOver; ++j)
        sum += f[kOver * i + j];
      y[i] += sum / kOver;
    }
  }
  // White PM: phase variance h2 f_h / (4 pi^2), f_h = 1/2 Hz. Flicker PM: Kasdin on the phase,
  // S_x = S_y / (2 pi f)^2, so h1 f / (4 pi^2 f^2) = h1 / (4 pi^2 f), a phase flicker level
  // h1 / (4 pi^2).
  if (t.h2 > 0 || t.h1 > 0) {
    const auto fx = kasdin_flicker(n + 1, kPi * t.h1 / (4 * kPi * kPi), rng);
    for (std::size_t i = 0; i <= n; ++i)
      x[i] = std::sqrt(t.h2 * 0.5 / (4 * kPi * kPi)) * g(rng) + (t.h1 > 0 ? fx[i] : 0.0);
    for (std::size_t i = 0; i < n; ++i)
      y[i] += x[i + 1] - x[i];
  }
  t.h0 += q_rw / 3.0;
  return y;
}

// White FM dominant below 32 s (h0 / (2 tau) = 2 ln2 h-1 there), flicker FM to 2000 s
// (2 ln2 h-1 = (2 pi^2 / 3) h-2 tau there), random-walk FM beyond.
Truth fm_clock() {
  Truth t;
  t.h0 = 1.0;
  t.hm1 = 1.0 / (2.0 * 32.0 * 2.0 * std::log(2.0));
  t.hm2 = 2.0 * std::log(2.0) * t.hm1 / (2.0 * kPi * kPi / 3.0 * 2000.0);
  return t;
}

pl::Result fit_clock(const std::vector<double>& y) {
  const k::PhaseData p = k::phase_from_rate(y, 1.0, 1);
  // Octave taus: a tenth of the default grid's, so that the covariance model costs little
  // under the sanitizers; the estimator is the same.
  const k::TauGridSpec grid = k::parse_tau_grid("octave");
  k::StatResult s[2];
  const k::Stat stats[2] = {k::Stat::Oadev, k::Stat::Mdev};
  for (int i = 0; i < 2; ++i) {
    const auto ms = k::stat_m_list(grid, stats[i], k::max_m(stats[i], p.n_points()), p.n_points());
    s[i] = k::compute(stats[i], p, ms, 1);
    k::add_confidence(stats[i], p, s[i], 0.683, 1);
  }
  return pl::fit(s[0], &s[1], 1.0);
}

// h0, h-1 and h-2 within 3 sigma of the truth in at least 5 of 6 seeds. With honest sigmas each
// seed misses with probability 0.0027 per level; 2 misses of 6 in one level have probability
// 1.1e-4 (and the sandwich's own error is absorbed by the margin between 3 sigma and the 2-miss
// allowance). The levels make white FM dominate below 30 s, flicker FM from there to 2000 s and
// random-walk FM beyond: 2^16 samples give all three a decade or more.
TEST(PowerLawFit, RecoversWhiteFlickerAndRandomWalkFm) {
  const std::size_t n = std::size_t{1} << 16;
  int within[3] = {0, 0, 0}, detected0 = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    Truth t = fm_clock();
    const auto y = clock(n, t, seed);
    const pl::Result r = fit_clock(y);
    ASSERT_EQ(r.status, pl::Status::Ok) << "seed " << seed;
    const double truth[3] = {t.h0, t.hm1, t.hm2};
    for (int a = 0; a < 3; ++a) {
      const pl::Level& l = r.at(-a);
      EXPECT_GT(l.h_sigma, 0.0);
      if (std::abs(l.h - truth[a]) < 3.0 * l.h_sigma) ++within[a];
      std::printf("seed %llu alpha %d: h %.4g +- %.3g (truth %.4g)%s\n",
                  static_cast<unsigned long long>(seed), -a, l.h, l.h_sigma, truth[a],
                  l.detected ? " detected" : "");
    }
    detected0 += r.at(0).detected ? 1 : 0;
  }
  for (int a = 0; a < 3; ++a)
    EXPECT_GE(within[a], 5) << "alpha " << -a;
  EXPECT_EQ(detected0, 6);
}

// MDEV tells white from flicker PM, which AVAR alone cannot: a clock of white PM and white FM
// has its white PM detected and flicker PM not; one of flicker PM and white FM has its flicker
// PM detected. (Kasdin's discrete flicker has more power than 1/f near its Nyquist frequency,
// which reads as some white PM: the converse is not asked.)
TEST(PowerLawFit, MdevSeparatesWhiteFromFlickerPm) {
  const std::size_t n = std::size_t{1} << 14;
  for (const int pm : {2, 1}) {
    Truth t;
    t.h0 = 1e-4;
    (pm == 2 ? t.h2 : t.h1) = 1.0;
    const pl::Result r = fit_clock(clock(n, t, 11));
    ASSERT_EQ(r.status, pl::Status::Ok);
    for (const int a : {2, 1})
      std::printf("%s clock: %s h %.4g +- %.3g\n", pl::noise_type_name(pm).data(),
                  pl::noise_type_name(a).data(), r.at(a).h, r.at(a).h_sigma);
    EXPECT_TRUE(r.at(pm).detected) << pl::noise_type_name(pm);
    if (pm == 2) {
      EXPECT_FALSE(r.at(1).detected);
    }
  }
}

// The coverage study of docs/validation/2026-11-28-clock-powerlaw.md, disabled by default (200
// seeds, a minute in a release build): the share of seeds with |h - truth| < k sigma for k = 1,
// 2, 3, per level, on the clocks of RecoversWhiteFlickerAndRandomWalkFm. Run with
// --gtest_also_run_disabled_tests --gtest_filter=PowerLawFit.DISABLED_CoverageStudy.
TEST(PowerLawFit, DISABLED_CoverageStudy) {
  const std::size_t n = std::size_t{1} << 16;
  constexpr int kSeeds = 200;
  int within[3][3] = {}, detected[3] = {};
  for (std::uint64_t seed = 1000; seed < 1000 + kSeeds; ++seed) {
    Truth t = fm_clock();
    const auto y = clock(n, t, seed);
    const pl::Result r = fit_clock(y);
    ASSERT_EQ(r.status, pl::Status::Ok);
    const double truth[3] = {t.h0, t.hm1, t.hm2};
    for (int a = 0; a < 3; ++a) {
      const pl::Level& l = r.at(-a);
      detected[a] += l.detected ? 1 : 0;
      for (int k = 0; k < 3; ++k)
        within[a][k] += std::abs(l.h - truth[a]) < (k + 1) * l.h_sigma ? 1 : 0;
    }
  }
  for (int a = 0; a < 3; ++a)
    std::printf("%-14s within 1/2/3 sigma: %.3f %.3f %.3f (normal 0.683 0.954 0.997); "
                "detected %.3f\n",
                pl::noise_type_name(-a).data(), within[a][0] / double(kSeeds),
                within[a][1] / double(kSeeds), within[a][2] / double(kSeeds),
                detected[a] / double(kSeeds));
}

// simulate's flicker PM (kernels::ChannelSpec::flicker_pm, Kasdin's sequence on the phase)
// against SP1065's AVAR of flicker PM, [1.038 + 3 ln(2 pi f_h tau)] h_1 / (4 pi^2 tau^2), and the
// power-law fit finding it. The relation is SP1065's approximation for a 1/f phase cut off at
// f_h; Kasdin's discrete sequence carries more power near Nyquist (its AVAR at m = 1 is 17 %
// above the relation), so from m = 4 on the tolerance is the estimates' chi-square spread (edf
// >= 2000 at m <= 64: 2 sqrt(2 / edf) < 7 %) plus 10 %.
TEST(PowerLawSimulate, FlickerPmHasSp1065sAllanVariance) {
  const std::size_t n = std::size_t{1} << 14;
  k::ChannelSpec spec;
  spec.rate_hz = 1.0;
  spec.flicker_pm = 1.0;
  std::vector<double> y(n);
  k::simulate_channel(spec, 5, 1, y, 1);
  const k::PhaseData p = k::phase_from_rate(y, 1.0, 1);
  const std::vector<std::int64_t> ms = {4, 16, 64};
  k::StatResult s = k::compute(k::Stat::Oadev, p, ms, 1);
  k::add_confidence(k::Stat::Oadev, p, s, 0.683, 1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double want = k::model_avar(spec, s.tau_s[i]);
    EXPECT_NEAR(s.dev[i] * s.dev[i] / want, 1.0, 2.0 * std::sqrt(2.0 / s.edf[i]) + 0.10)
        << "m " << s.m[i];
    EXPECT_DOUBLE_EQ(want, pl::avar_per_h(1, s.tau_s[i], 1.0));
  }
}

TEST(PowerLawFit, NeedsMdevAndRows) {
  k::StatResult empty;
  EXPECT_EQ(pl::fit(empty, nullptr, 1.0).status, pl::Status::NoData);
  EXPECT_THROW(pl::fit(empty, nullptr, 0.0), std::invalid_argument);
}

}  // namespace
