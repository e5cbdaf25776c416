// Welch PSD, log binning and eq. (2) on the measured PSD (kernels/spectral/psd.hpp).
//
// Statistical checks compare a Welch value of edf nu with its expectation through
// z = (ln(P / P_model) + 1/nu) / sqrt(2 / nu) (ln of a chi-square average: mean -1/nu, sd
// sqrt(2/nu)) and the gap sqrt(mean z^2) over the bins, as test_simulate.cpp does for the
// Allan variance; kMaxGap = 3 fails a correct estimator rarely (even if every z were equal,
// P(|z| > 3) = 0.27 %), and each such test also shows that a 10 % error in a coefficient
// is detected.
#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/spectral/psd.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot {
namespace {

using kernels::ChannelSpec;

constexpr double kMaxGap = 3.0;
constexpr std::uint64_t kSeed = 20261122;

std::vector<double> simulate(const ChannelSpec& spec, std::size_t n, std::uint64_t stream) {
  std::vector<double> y(n);
  kernels::simulate_channel(spec, kSeed, stream, y, 0);
  return y;
}

ChannelSpec white_spec(double rate_hz, double N) {
  ChannelSpec s;
  s.rate_hz = rate_hz;
  s.terms.N = N;
  return s;
}

// The paper's gyro X levels (table of the paper; docs/formats.md units: deg/s and seconds).
ChannelSpec gyro_spec() {
  ChannelSpec s;
  s.rate_hz = 1000;
  s.terms.N = 0.005;
  s.terms.B = 0.00125;
  s.terms.K = 4.63e-7;
  return s;
}

// 2^21 samples (35 min at 1 kHz): long enough that the lowest unbiased Welch bin (2 df =
// 0.015 Hz) is near the flicker/white corner B^2 / (2 pi N^2) = 0.01 Hz, short enough for an
// ASan build. Simulated once for every test of this program.
const std::vector<double>& gyro_data() {
  static const std::vector<double> y = simulate(gyro_spec(), std::size_t{1} << 21, 7);
  return y;
}

double gap(const kernels::BinnedPsd& b, double f_lo, double f_hi,
           const std::function<double(double)>& model, int* n_used = nullptr) {
  double s = 0;
  int n = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.f_hz[i] < f_lo || b.f_hz[i] > f_hi) continue;
    const double z =
        (std::log(b.psd[i] / model(b.f_hz[i])) + 1 / b.edf[i]) / std::sqrt(2 / b.edf[i]);
    s += z * z;
    ++n;
  }
  if (n_used) *n_used = n;
  return n ? std::sqrt(s / n) : std::numeric_limits<double>::infinity();
}

template <class F>
void expect_invalid(F&& f, const std::string& name) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected std::invalid_argument naming " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------

TEST(PsdSegmentRule, PowerOfTwoWithAtLeastMinSegments) {
  for (std::int64_t n : {136LL, 1000LL, 65536LL, 1000003LL, 1LL << 21, 5400000LL}) {
    const auto L = kernels::welch_segment_length(n);
    EXPECT_EQ(L & (L - 1), 0) << n;
    EXPECT_GE(kernels::welch_segment_count(n, L), 16) << n;
    EXPECT_LT(kernels::welch_segment_count(n, 2 * L), 16) << n;
  }
  EXPECT_EQ(kernels::welch_segment_length(std::int64_t{1} << 21), std::int64_t{1} << 17);
  EXPECT_EQ(kernels::welch_segment_count(100, 16), 11);  // starts 0, 8, ..., 80
  EXPECT_EQ(kernels::welch_segment_length(1000, 4), 256);
}

// Discrete Parseval: sum_k psd_k df equals the mean over segments of the window-weighted mean
// square of each mean-removed segment (exact, computed here independently in long double), and
// that equals the variance of the data within the window's statistical weighting (a few
// tenths of a percent for 2^18 samples; a wrong window power sum w vs sum w^2 would be 33 %
// off, a missing one-sided factor 2 50 %).
TEST(PsdParseval, ExactIdentityAndVariance) {
  ChannelSpec spec = white_spec(100, 0.01);
  spec.markovs.push_back({0.02, 0.05});  // coloured, but all power above df = 0.4 Hz
  spec.offset = 3.0;
  const auto y = simulate(spec, std::size_t{1} << 18, 1);
  const auto r = kernels::welch_psd(y, spec.rate_hz, 0);
  ASSERT_EQ(r.segment_length, 1 << 14);
  double total = 0;
  for (std::size_t k = 0; k < r.size(); ++k)
    total += r.psd[k] * r.df_hz;

  const auto L = static_cast<std::size_t>(r.segment_length);
  long double acc = 0;
  for (std::int64_t j = 0; j < r.n_segments; ++j) {
    const std::size_t s0 = static_cast<std::size_t>(j) * L / 2;
    long double mean = 0;
    for (std::size_t t = 0; t < L; ++t)
      mean += y[s0 + t];
    mean /= L;
    long double num = 0, den = 0;
    for (std::size_t t = 0; t < L; ++t) {
      const long double w = 0.5L - 0.5L * std::cos(2 * std::numbers::pi_v<long double> * t / L);
      num += w * w * (y[s0 + t] - mean) * (y[s0 + t] - mean);
      den += w * w;
    }
    acc += num / den;
  }
  const double exact = static_cast<double>(acc / r.n_segments);
  EXPECT_NEAR(total / exact - 1, 0, 1e-12);

  long double m = 0, v = 0;
  for (double x : y)
    m += x;
  m /= y.size();
  for (double x : y)
    v += (x - m) * (x - m);
  const double var = static_cast<double>(v / y.size());
  const double err = total / var - 1;
  RecordProperty("parseval_rel_error", std::to_string(err));
  std::printf("Parseval: sum psd df / variance - 1 = %.3e\n", err);
  EXPECT_LT(std::abs(err), 0.02);
}

// White noise of coefficient N: flat one-sided PSD 2 N^2, each bin chi-square with the
// reported edf (checked through the scatter of the bins), and the log-binned values within
// their chi-square band (checked through the z gap, which also validates log_bin's edf).
TEST(PsdWhite, FlatAtTwoNSquaredWithinChiSquareBand) {
  const double N = 0.005, fs = 1000;
  const auto y = simulate(white_spec(fs, N), std::size_t{1} << 18, 2);
  const auto r = kernels::welch_psd(y, fs, 0);
  EXPECT_EQ(r.n_segments, 31);
  EXPECT_EQ(r.n_skipped, 0);
  const double nu = r.edf[5];
  EXPECT_NEAR(nu, 2.0 * 31 * 31 / (31 + 2.0 / 36 * 30), 1e-9);  // rho = 1/6 for Hann
  const double level = 2 * N * N;
  const double lo = kernels::chi2_quantile(0.005, nu) / nu;
  const double hi = kernels::chi2_quantile(0.995, nu) / nu;
  double s = 0, s2 = 0;
  int n = 0, out = 0;
  for (std::size_t k = 2; k + 1 < r.size(); ++k) {
    const double q = r.psd[k] / level;
    s += q, s2 += q * q, ++n;
    if (q < lo || q > hi) ++out;
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  // Mean over ~8000 bins: sd ~ sqrt(2/nu) * sqrt(1.9 / 8000) = 0.003.
  EXPECT_NEAR(mean, 1, 0.015);
  EXPECT_GT(std::abs(mean * 1.21 - 1), 0.1);  // a 10 % error in N would be seen
  // Scatter of the bins: 2/nu within ~10 % (sd of a sample variance of ~4000 effective bins
  // is ~2.5 %); an edf ignoring the overlap correlation, or 2 n_seg, would be >= 5 % off,
  // and a periodogram of the whole record (nu = 2) hugely.
  EXPECT_NEAR(var * nu / 2, 1, 0.1);
  const double frac = static_cast<double>(out) / n;
  std::printf("white: mean %.4f, var*nu/2 %.3f, outside 99%% band %.4f\n", mean, var * nu / 2,
              frac);
  EXPECT_GT(frac, 0.002);
  EXPECT_LT(frac, 0.025);

  const auto b = kernels::log_bin(r, 10, 4);
  int used = 0;
  const double g = gap(
      b, 2 * r.df_hz, fs / 2, [&](double) { return level; }, &used);
  EXPECT_GT(used, 30);
  EXPECT_LT(g, kMaxGap);
  EXPECT_GT(g, 0.3);  // an edf much too small would hide any error
  EXPECT_GT(gap(b, 2 * r.df_hz, fs / 2, [&](double) { return level * 1.21; }), kMaxGap);
  for (std::size_t i = 0; i < b.size(); ++i)
    EXPECT_GE(b.n_avg[i], 1);
}

TEST(PsdLogBin, KeepsLinearBinsAndCountsAveraged) {
  kernels::PsdResult p;
  p.rate_hz = 64;
  p.segment_length = 64;
  p.df_hz = 1;
  for (int k = 0; k <= 32; ++k) {
    p.f_hz.push_back(k);
    p.psd.push_back(1.0 + k);
    p.edf.push_back(10);
  }
  const auto b = kernels::log_bin(p, 2, 3);  // edges 1, 3.16, 10, 31.6, 100
  ASSERT_EQ(b.size(), 3u + 2u + 1u);
  // Linear bins 1, 2, 3; then [3.16, 10) -> 4..9; [10, 31.6) -> 10..31; [31.6, 100) -> 32.
  EXPECT_EQ(b.n_avg, (std::vector<std::int64_t>{1, 1, 1, 6, 22, 1}));
  EXPECT_DOUBLE_EQ(b.f_hz[3], 6.5);
  EXPECT_DOUBLE_EQ(b.psd[3], 7.5);
  EXPECT_DOUBLE_EQ(b.f_hz[5], 32);
  // edf of a mean of 6 Hann bins: 10 * 36 / (6 + 2 * 5 * 4/9 + 2 * 4 / 36).
  EXPECT_NEAR(b.edf[3], 10.0 * 36 / (6 + 10 * 4.0 / 9 + 8.0 / 36), 1e-9);
  EXPECT_EQ(b.edf[0], 10);
  // The Hann bin correlations log_bin uses, against the direct sum over the window.
  for (const int L : {16, 64, 1 << 12}) {
    double s2 = 0, re[4] = {}, im[4] = {};
    for (int t = 0; t < L; ++t) {
      const double w = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * t / L);
      s2 += w * w;
      for (int d = 1; d <= 3; ++d) {
        re[d] += w * w * std::cos(2 * std::numbers::pi * d * t / L);
        im[d] += w * w * std::sin(2 * std::numbers::pi * d * t / L);
      }
    }
    const double want[4] = {1, 4.0 / 9, 1.0 / 36, 0};
    for (int d = 1; d <= 3; ++d)
      EXPECT_NEAR((re[d] * re[d] + im[d] * im[d]) / (s2 * s2), want[d], 1e-12) << L << " " << d;
  }
}

// The paper's gyro X: measured PSD against model_psd_one_sided over mid frequencies (from the
// first unbiased bins to fs/4, where the continuous-time forms hold).
TEST(PsdGyro, MatchesModelWithinBand) {
  const auto spec = gyro_spec();
  const auto& y = gyro_data();
  const auto r = kernels::welch_psd(y, spec.rate_hz, 0);
  const auto b = kernels::log_bin(r, 10, 4);
  const auto model = [&](double f) { return kernels::model_psd_one_sided(spec, f); };
  int used = 0;
  const double g = gap(b, 3 * r.df_hz, spec.rate_hz / 4, model, &used);
  std::printf("gyro PSD: L = %lld, segments %lld, gap %.3f over %d binned values\n",
              static_cast<long long>(r.segment_length), static_cast<long long>(r.n_segments), g,
              used);
  EXPECT_GT(used, 25);
  EXPECT_LT(g, kMaxGap);
  auto wrong = spec;
  wrong.terms.N *= 1.1;
  EXPECT_GT(gap(b, 3 * r.df_hz, spec.rate_hz / 4,
                [&](double f) { return kernels::model_psd_one_sided(wrong, f); }),
            kMaxGap);
}

// |H_m|^2 integrates white noise exactly: integral_0^{fs/2} 2 N^2 |H_m|^2 df = N^2 / (m tau0)
// for every integer m (the discrete white-noise Allan variance), while the continuous
// kernel cut at Nyquist gives 0.645 N^2 / tau0 at m = 1 (35 % low).
TEST(PsdEq2, DiscreteKernelIsExactForSampledWhiteNoise) {
  const double fs = 10, N = 1;
  for (int m : {1, 2, 3, 10, 64}) {
    const double tau = m / fs;
    const int n = 200000;
    const double h = fs / 2 / n;
    double s = 0;
    for (int i = 0; i < n; ++i)
      s += 2 * N * N * kernels::allan_kernel_discrete((i + 0.5) * h, tau, fs) * h;
    EXPECT_NEAR(s / (N * N / tau), 1, 1e-6) << m;
  }
  double c = 0;
  const int n = 200000;
  const double h = fs / 2 / n, tau = 1 / fs;
  for (int i = 0; i < n; ++i) {
    const double u = std::numbers::pi * (i + 0.5) * h * tau;
    c += 4 * N * N * std::pow(std::sin(u), 4) / (u * u) * h;  // 2 N^2 * 2 sin^4 / u^2
  }
  EXPECT_NEAR(c / (N * N / tau), 0.645, 0.005);
}

// Eq. (2) on the measured PSD against the overlapping Allan variance of the same data.
TEST(PsdEq2, CrossCheckAgainstOadev) {
  const auto spec = gyro_spec();
  const auto& y = gyro_data();
  const auto r = kernels::welch_psd(y, spec.rate_hz, 0);
  std::vector<std::int64_t> ms;
  for (double m = 1; m <= static_cast<double>(y.size()) / 4; m *= std::pow(10.0, 0.2)) {
    const auto mi = static_cast<std::int64_t>(std::llround(m));
    if (ms.empty() || mi != ms.back()) ms.push_back(mi);
  }
  const auto od = kernels::oadev(kernels::phase_from_rate(y, spec.rate_hz), ms, 0);
  ASSERT_EQ(od.size(), ms.size());
  std::vector<double> taus;
  for (auto m : ms)
    taus.push_back(static_cast<double>(m) / spec.rate_hz);
  const auto a = kernels::avar_from_psd(r, taus);
  ASSERT_TRUE(a.low_fit_ok);
  // The lowest decade is flicker plus white: an exponent between -1 and 0.
  EXPECT_GT(a.low_exponent, -1.5);
  EXPECT_LT(a.low_exponent, 0.3);
  double worst = 0;
  int n_valid = 0;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const double ratio = a.avar[i] / (od.dev[i] * od.dev[i]);
    if (!a.valid[i]) continue;
    ++n_valid;
    worst = std::max(worst, std::abs(ratio - 1));
    EXPECT_NEAR(ratio, 1, 0.12) << "tau " << taus[i] << " low share " << a.avar_low[i] / a.avar[i];
  }
  std::printf("crosscheck: valid tau %.4g .. %.4g s (%d taus), max |ratio - 1| = %.4f, "
              "low-f fit a = %.3f\n",
              a.tau_valid_min, a.tau_valid_max, n_valid, worst, a.low_exponent);
  RecordProperty("crosscheck_max_rel_dev", std::to_string(worst));
  EXPECT_EQ(a.tau_valid_min, taus.front());
  EXPECT_GE(a.tau_valid_max, 5.0);  // white and the start of the flicker floor
  // The valid taus form one interval starting at tau0.
  bool seen_invalid = false;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    if (!a.valid[i]) seen_invalid = true;
    if (seen_invalid) {
      EXPECT_FALSE(a.valid[i]) << taus[i];
    }
  }
  EXPECT_TRUE(seen_invalid);  // the record's longest taus are beyond the PSD's resolution
}

// A narrow-band disturbance: a line at f0 = 0.05 Hz (period 20 s, as a thermal cycle or a
// rotating-table wobble would give) strong enough to dominate the Allan curve around
// tau ~ 0.37 / f0. The Allan variance of a sinusoid is A^2 sin^4(pi f0 tau) / (pi f0 tau)^2
// (kernel of eq. (2) at one frequency), zero at tau = 1 / f0; the Welch PSD cannot hold a line:
// Hann spreads it over +-2 bins (+-0.015 Hz here, 30 % of f0), and eq. (2) on that smeared
// line does not fall to zero at 1 / f0. So the cross-check must (a) stay within 12 % where the
// line is resolved by the kernel (tau <= 0.25 / f0: the kernel's first lobe is many bins
// wide), and (b) depart by far more than 12 % approaching the kernel's zero, with its worst
// tau between 0.5 / f0 and 1 / f0. That is what the crosscheck/ datasets and the summary's
// max_abs_log10_ratio and crosscheck_worst_tau show the user.
TEST(PsdEq2, CrossCheckDepartsNearALowFrequencyLine) {
  auto spec = gyro_spec();
  const double A = 0.05, f0 = 0.05;
  spec.sinusoids.push_back({A, f0, 0.3});
  const auto y = simulate(spec, std::size_t{1} << 21, 9);
  const auto r = kernels::welch_psd(y, spec.rate_hz, 0);
  std::vector<std::int64_t> ms;
  for (double m = 1; m <= static_cast<double>(y.size()) / 4; m *= std::pow(10.0, 1.0 / 16)) {
    const auto mi = static_cast<std::int64_t>(std::llround(m));
    if (ms.empty() || mi != ms.back()) ms.push_back(mi);
  }
  const auto od = kernels::oadev(kernels::phase_from_rate(y, spec.rate_hz), ms, 0);
  std::vector<double> taus;
  for (auto m : ms)
    taus.push_back(static_cast<double>(m) / spec.rate_hz);
  const auto a = kernels::avar_from_psd(r, taus);
  double worst = 0, worst_tau = 0, worst_resolved = 0;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    if (!a.valid[i]) continue;
    const double d = std::abs(std::log10(a.avar[i] / (od.dev[i] * od.dev[i])));
    if (taus[i] <= 0.25 / f0) worst_resolved = std::max(worst_resolved, d);
    if (d > worst) {
      worst = d;
      worst_tau = taus[i];
    }
  }
  std::printf("line at %.3g Hz: |log10 ratio| <= %.4f up to tau = %.3g s; worst %.4f "
              "(ratio %.3g) at tau = %.4g s; valid up to %.4g s\n",
              f0, worst_resolved, 0.25 / f0, worst, std::pow(10.0, worst), worst_tau,
              a.tau_valid_max);
  EXPECT_LE(worst_resolved, std::log10(1.12));
  EXPECT_GT(worst, std::log10(1.3));
  EXPECT_GE(worst_tau, 0.5 / f0);
  EXPECT_LE(worst_tau, 1.0 / f0);
}

TEST(PsdSinusoid, LineAtItsFrequencyWithItsPower) {
  auto spec = white_spec(1000, 0.005);
  const double A = 0.02, f0 = 37.3;
  spec.sinusoids.push_back({A, f0, 0.4});
  const auto y = simulate(spec, std::size_t{1} << 18, 3);
  const auto r = kernels::welch_psd(y, spec.rate_hz, 0);
  const auto peak =
      static_cast<std::size_t>(std::max_element(r.psd.begin() + 2, r.psd.end()) - r.psd.begin());
  EXPECT_NEAR(r.f_hz[peak], f0, r.df_hz);
  EXPECT_GT(r.psd[peak], 20 * 2 * 0.005 * 0.005);  // ~ A^2/2 / (1.5 df): 43 x the floor
  // Power in +-3 bins above the noise floor: the line's A^2 / 2 (Hann's main lobe holds all
  // but ~1e-4 of it; the floor's scatter over 7 bins is ~1 % of the line).
  double p = 0;
  for (std::size_t k = peak - 3; k <= peak + 3; ++k)
    p += (r.psd[k] - 2 * 0.005 * 0.005) * r.df_hz;
  EXPECT_NEAR(p / (A * A / 2), 1, 0.05);
}

TEST(PsdThreads, BitIdenticalFor1_2_7Threads) {
  const auto& full = gyro_data();
  std::vector<double> y(full.begin(), full.begin() + (1 << 19));
  y[100000] = std::numeric_limits<double>::quiet_NaN();  // a gap: two segments skipped
  const kernels::PsdPlan plan(kernels::welch_segment_length(static_cast<std::int64_t>(y.size())));
  const auto r1 = plan.welch(y, 1000, 1);
  EXPECT_EQ(r1.n_skipped, 2);
  EXPECT_EQ(r1.n_segments + r1.n_skipped, kernels::welch_segment_count(1 << 19, 1 << 15));
  std::vector<double> taus;
  for (double t = 1e-3; t < 10; t *= 1.7)
    taus.push_back(t);
  const auto a1 = kernels::avar_from_psd(r1, taus, {}, 1);
  for (int nt : {2, 7}) {
    const auto r = plan.welch(y, 1000, nt);
    EXPECT_EQ(r.psd, r1.psd) << nt;
    EXPECT_EQ(r.edf, r1.edf) << nt;
    const auto a = kernels::avar_from_psd(r, taus, {}, nt);
    EXPECT_EQ(a.avar, a1.avar) << nt;
    EXPECT_EQ(a.valid, a1.valid) << nt;
  }
  // The plan is reusable across channels: a second channel, then the first again.
  const auto other = plan.welch(std::span<const double>(full).subspan(1 << 19, 1 << 19), 1000, 2);
  EXPECT_NE(other.psd, r1.psd);
  EXPECT_EQ(plan.welch(y, 1000, 2).psd, r1.psd);
}

TEST(PsdDumbInputs, ThrowNamingTheParameter) {
  const std::vector<double> short_y(100, 1.0);
  expect_invalid([&] { kernels::welch_psd(short_y, 1000); }, "n_samples");
  expect_invalid([&] { kernels::welch_psd({}, 1000); }, "n_samples");
  const kernels::PsdPlan plan(64);
  expect_invalid([&] { plan.welch(std::span<const double>(short_y).first(10), 1000); }, "rate");
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()})
    expect_invalid([&] { plan.welch(short_y, bad); }, "rate_hz");
  const std::vector<double> nan_y(1000, std::numeric_limits<double>::quiet_NaN());
  expect_invalid([&] { plan.welch(nan_y, 1000); }, "rate");
  expect_invalid([&] { kernels::welch_psd(nan_y, 1000); }, "rate");
  auto inf_y = short_y;
  inf_y[7] = -std::numeric_limits<double>::infinity();
  expect_invalid([&] { plan.welch(inf_y, 1000); }, "rate");
  for (std::int64_t L : {0LL, 8LL, 15LL, 65LL, -64LL})
    expect_invalid([&] { kernels::PsdPlan p(L); }, "segment_length");
  expect_invalid([&] { kernels::welch_segment_length(1000, 0); }, "min_segments");
  const auto r = plan.welch(std::vector<double>(1000, 0.5), 1000);
  expect_invalid([&] { kernels::log_bin(r, 0); }, "bins_per_decade");
  expect_invalid([&] { kernels::log_bin(r, 10, -1); }, "n_linear");
  const std::vector<double> bad_tau{1e-4};
  expect_invalid([&] { kernels::avar_from_psd(r, bad_tau); }, "tau_s");
  const std::vector<double> nan_tau{std::numeric_limits<double>::quiet_NaN()};
  expect_invalid([&] { kernels::avar_from_psd(r, nan_tau); }, "tau_s");
  kernels::AvarPsdOptions o;
  o.first_bin = 0;
  expect_invalid([&] { kernels::avar_from_psd(r, {}, o); }, "first_bin");
  // A constant channel has a zero PSD: no power law can be fitted, and nothing is valid.
  const std::vector<double> tau{0.01};
  const auto a = kernels::avar_from_psd(r, tau);
  EXPECT_FALSE(a.low_fit_ok);
  EXPECT_EQ(a.valid[0], 0);
  EXPECT_TRUE(std::isnan(a.tau_valid_min));
}

// The stored FFTW wisdom (kernels/spectral/fft_wisdom.txt) must plan every Welch length on this
// project's machine kind: where it does not (a new FFTW in Debian, or a new machine kind), the
// PSD silently falls back to FFTW_ESTIMATE's plans, twice as slow (docs/performance.md), and
// bench/make_fft_wisdom must be run again. The wisdom holds AVX-512 plans, so a CPU without
// AVX-512 cannot use them; there the fallback is the expected outcome.
TEST(PsdPlans, WelchLengthsComeFromTheStoredWisdom) {
  if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "no AVX-512: FFTW_ESTIMATE plans";
  for (std::int64_t L = 16; L <= (std::int64_t{1} << 20); L *= 2)
    EXPECT_TRUE(kernels::PsdPlan::shared(L).from_wisdom()) << "segment length " << L;
  // An odd-sized transform is not in the wisdom: FFTW_ESTIMATE plans it, and it still works.
  const kernels::PsdPlan odd(1000);
  EXPECT_FALSE(odd.from_wisdom());
}

// The shared plan of a length is one object, and a Welch PSD through it equals one through a
// plan of its own, bit for bit.
TEST(PsdPlans, SharedPlanIsOneAndRoundsAsAFreshOne) {
  const std::int64_t L = 256;
  EXPECT_EQ(&kernels::PsdPlan::shared(L), &kernels::PsdPlan::shared(L));
  std::vector<double> y(4096);
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] = std::sin(0.37 * static_cast<double>(i)) + 1e-3 * static_cast<double>(i % 17);
  const kernels::PsdPlan fresh(L);
  const kernels::PsdResult a = kernels::PsdPlan::shared(L).welch(y, 100.0, 1);
  const kernels::PsdResult b = fresh.welch(y, 100.0, 2);
  EXPECT_EQ(a.psd, b.psd);
}

}  // namespace
}  // namespace allanlot
