// Statistical check of the confidence intervals on simulated white, flicker and random-walk FM:
// over many seeds the fraction of intervals that contain the true deviation must match the
// stated confidence, and on one long record the deviations must follow their theoretical
// slopes within the reported intervals.
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <fftw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <random>
#include <vector>

namespace allanlot {
namespace {

using kernels::Stat;

enum class Noise { WhiteFm, FlickerFm, RandomWalkFm };

// Kasdin & Walter's fractional integration filter for S_y ~ f^-1 (Proc. 1992 IEEE FCS,
// eq. (14) with alpha = 1 of their f^-alpha convention): h_0 = 1, h_k = h_{k-1} (k - 1/2) / k.
std::vector<double> flicker_filter(std::size_t n) {
  std::vector<double> h(n);
  h[0] = 1.0;
  for (std::size_t k = 1; k < n; ++k)
    h[k] = h[k - 1] * (static_cast<double>(k) - 0.5) / static_cast<double>(k);
  return h;
}

// Generates rate samples; flicker FM is the filter applied to white noise by FFT convolution
// (O(N log N)), after a warm-up of kWarmup samples that is discarded so that the record has
// the stationary increments of the infinite-past process (the filter's memory beyond the
// warm-up changes the Allan variance at m <= 64 by < 1e-6).
class Generator {
public:
  static constexpr std::size_t kWarmup = 1 << 16;
  explicit Generator(std::size_t n) : n_(n), len_(kWarmup + n) {
    fft_n_ = 1;
    while (fft_n_ < 2 * len_)
      fft_n_ *= 2;
    buf_ = fftw_alloc_real(fft_n_);
    spec_ = fftw_alloc_complex(fft_n_ / 2 + 1);
    hspec_.resize(fft_n_ / 2 + 1);
    fwd_ = fftw_plan_dft_r2c_1d(static_cast<int>(fft_n_), buf_, spec_, FFTW_ESTIMATE);
    inv_ = fftw_plan_dft_c2r_1d(static_cast<int>(fft_n_), spec_, buf_, FFTW_ESTIMATE);
    const auto h = flicker_filter(len_);
    std::fill(buf_, buf_ + fft_n_, 0.0);
    std::copy(h.begin(), h.end(), buf_);
    fftw_execute(fwd_);
    for (std::size_t k = 0; k < hspec_.size(); ++k)
      hspec_[k] = {spec_[k][0], spec_[k][1]};
  }
  ~Generator() {
    fftw_destroy_plan(fwd_);
    fftw_destroy_plan(inv_);
    fftw_free(buf_);
    fftw_free(spec_);
  }
  Generator(const Generator&) = delete;
  Generator& operator=(const Generator&) = delete;

  std::vector<double> operator()(Noise noise, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> y(n_);
    if (noise == Noise::WhiteFm) {
      for (auto& v : y)
        v = g(rng);
    } else if (noise == Noise::RandomWalkFm) {
      double walk = 0.0;
      for (auto& v : y)
        v = walk += g(rng);
    } else {
      std::fill(buf_, buf_ + fft_n_, 0.0);
      for (std::size_t k = 0; k < len_; ++k)
        buf_[k] = g(rng);
      fftw_execute(fwd_);
      for (std::size_t k = 0; k < hspec_.size(); ++k) {
        const std::complex<double> v = std::complex<double>(spec_[k][0], spec_[k][1]) * hspec_[k];
        spec_[k][0] = v.real() / static_cast<double>(fft_n_);  // FFTW's c2r is unnormalized
        spec_[k][1] = v.imag() / static_cast<double>(fft_n_);
      }
      fftw_execute(inv_);
      std::copy(buf_ + kWarmup, buf_ + len_, y.begin());
    }
    return y;
  }

private:
  std::size_t n_, len_, fft_n_ = 0;
  double* buf_ = nullptr;
  fftw_complex* spec_ = nullptr;
  std::vector<std::complex<double>> hspec_;
  fftw_plan fwd_ = nullptr, inv_ = nullptr;
};

// True Allan deviation of unit-variance driving noise at averaging factor m (tau0 = 1):
// white FM 1/m (SP1065 Table 5 with h0 = 2); random-walk FM (2m^2 + 1)/(6m) (the m-sample
// average difference weights the increments 1, 2, .., m, .., 1); flicker FM from the filter:
// the difference of two adjacent m-sample averages of y = h * w weights w_{s-v} by
// c(v) = H(v+2m-1) - 2H(v+m-1) + H(v-1) with H the cumulative sum of h, so
// AVAR = sum_v c(v)^2 / (2 m^2), summed to V = 2^20 plus the tail of c(v)^2 ~
// m^4 v^-3 / (16 Gamma(3/2)^2), whose integral beyond V is m^4 / (32 Gamma(3/2)^2 V^2).
double true_adev(Noise noise, std::int64_t m) {
  const double md = static_cast<double>(m);
  if (noise == Noise::WhiteFm) return std::sqrt(1.0 / md);
  if (noise == Noise::RandomWalkFm) return std::sqrt((2.0 * md * md + 1.0) / (6.0 * md));
  const std::int64_t V = 1 << 20;
  const auto h = flicker_filter(static_cast<std::size_t>(V + 2 * m));
  std::vector<double> H(h.size());
  double acc = 0.0;
  for (std::size_t k = 0; k < h.size(); ++k)
    H[k] = acc += h[k];
  const auto Hat = [&](std::int64_t k) { return k < 0 ? 0.0 : H[static_cast<std::size_t>(k)]; };
  long double sum = 0.0L;
  for (std::int64_t v = -(2 * m - 1); v < V; ++v) {
    const double c = Hat(v + 2 * m - 1) - 2.0 * Hat(v + m - 1) + Hat(v - 1);
    sum += static_cast<long double>(c) * c;
  }
  const double gamma15 = std::tgamma(1.5);
  const double tail = md * md * md * md / (32.0 * gamma15 * gamma15 * double(V) * double(V));
  return std::sqrt((static_cast<double>(sum) + tail) / (2.0 * md * md));
}

const char* noise_name(Noise n) {
  return n == Noise::WhiteFm ? "white FM" : n == Noise::FlickerFm ? "flicker FM" : "random-walk FM";
}

// Coverage: kTrials independent records; at each m the number of intervals containing the
// true deviation is Binomial(kTrials, c) if the intervals are exact. The acceptance band is
// that count's mean +- 4 standard deviations, kTrials c +- 4 sqrt(kTrials c (1 - c)): a correct
// implementation fails one check with probability 6e-5 (each of the 12 checks), and with
// kTrials = 300 the band is +-0.107 around c = 0.683.
TEST(ConfidenceCoverage, FractionOfIntervalsContainingTruth) {
  constexpr int kTrials = 300;
  constexpr double kC = 0.683;
  const std::vector<std::int64_t> ms = {1, 4, 16, 64};
  Generator gen(4096);
  for (const Noise noise : {Noise::WhiteFm, Noise::FlickerFm, Noise::RandomWalkFm}) {
    std::vector<double> truth;
    for (const auto m : ms)
      truth.push_back(true_adev(noise, m));
    std::vector<int> hits(ms.size(), 0), alpha_right(ms.size(), 0);
    const int true_alpha = noise == Noise::WhiteFm ? 0 : noise == Noise::FlickerFm ? -1 : -2;
    for (int t = 0; t < kTrials; ++t) {
      const auto y = gen(noise, 1000 + static_cast<std::uint64_t>(t));
      const auto p = kernels::phase_from_rate(y, 1.0, 1);
      auto r = kernels::compute(Stat::Oadev, p, ms, 1);
      ASSERT_EQ(r.size(), ms.size());
      kernels::add_confidence(Stat::Oadev, p, r, kC, 1);
      for (std::size_t i = 0; i < ms.size(); ++i) {
        if (r.dev_lo[i] <= truth[i] && truth[i] <= r.dev_hi[i]) ++hits[i];
        if (r.alpha[i] == true_alpha) ++alpha_right[i];
      }
    }
    const double sd = std::sqrt(kTrials * kC * (1.0 - kC));
    for (std::size_t i = 0; i < ms.size(); ++i) {
      std::printf("%-15s m=%3lld coverage %.3f (band %.3f..%.3f)  alpha right %.2f\n",
                  noise_name(noise), static_cast<long long>(ms[i]),
                  static_cast<double>(hits[i]) / kTrials, kC - 4 * sd / kTrials,
                  kC + 4 * sd / kTrials, static_cast<double>(alpha_right[i]) / kTrials);
      EXPECT_NEAR(hits[i], kTrials * kC, 4.0 * sd) << noise_name(noise) << " m=" << ms[i];
      // The lag-1 method on >= 64 averages identifies white and random-walk FM in nearly every
      // record (observed >= 0.92). Averaged flicker FM is harder: after two differences delta
      // sits near -0.5 with the rounding boundaries at -0.25 and -0.75, and with 256 or 64
      // averages (m = 16, 64) only 0.64 and 0.56 of the records land inside (1.00 and 0.93 at
      // m = 1, 4); the intervals keep their coverage regardless, as checked above.
      const double min_right = noise == Noise::FlickerFm && ms[i] >= 16 ? 0.5 : 0.9;
      EXPECT_GT(alpha_right[i], min_right * kTrials) << noise_name(noise) << " m=" << ms[i];
    }
  }
}

// One long record per noise: the theoretical deviation lies within the 99.9 % interval at
// every octave m (a fixed seed; a correct implementation misses one of the ~36 points with
// probability ~3 %), and the log-log slope of the estimates is the theoretical -1/2, 0, +1/2
// within 0.1.
TEST(ConfidenceCoverage, SlopesWithinReportedIntervals) {
  const std::size_t n = 1 << 17;
  Generator gen(n);
  std::vector<std::int64_t> ms;
  for (std::int64_t m = 1; m <= static_cast<std::int64_t>(n) / 64; m *= 2)
    ms.push_back(m);
  for (const Noise noise : {Noise::WhiteFm, Noise::FlickerFm, Noise::RandomWalkFm}) {
    const auto y = gen(noise, 77);
    const auto p = kernels::phase_from_rate(y, 1.0, 1);
    auto r = kernels::compute(Stat::Oadev, p, ms, 2);
    kernels::add_confidence(Stat::Oadev, p, r, 0.999, 2);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double truth = true_adev(noise, r.m[i]);
      EXPECT_LE(r.dev_lo[i], truth) << noise_name(noise) << " m=" << r.m[i];
      EXPECT_GE(r.dev_hi[i], truth) << noise_name(noise) << " m=" << r.m[i];
      const double lx = std::log(static_cast<double>(r.m[i])), ly = std::log(r.dev[i]);
      sx += lx;
      sy += ly;
      sxx += lx * lx;
      sxy += lx * ly;
    }
    const double k = static_cast<double>(r.size());
    const double slope = (k * sxy - sx * sy) / (k * sxx - sx * sx);
    const double expected = noise == Noise::WhiteFm ? -0.5 : noise == Noise::FlickerFm ? 0.0 : 0.5;
    EXPECT_NEAR(slope, expected, 0.1) << noise_name(noise);
  }
}

}  // namespace
}  // namespace allanlot
