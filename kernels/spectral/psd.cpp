// Welch PSD, log binning and eq. (2) on the measured PSD; see psd.hpp for the math.
#include "kernels/spectral/psd.hpp"

#include "kernels/common/large_vector.hpp"
#include "kernels/common/parallel.hpp"
#include "kernels/spectral/fft.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

constexpr std::int64_t kMinSegment = 16;
constexpr std::int64_t kMaxSegment = std::int64_t{1} << 30;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void check_rate(double rate_hz, const char* who) {
  if (!std::isfinite(rate_hz) || rate_hz <= 0)
    throw std::invalid_argument(std::string(who) + ": rate_hz must be finite and > 0, got " +
                                num(rate_hz));
}

}  // namespace

std::int64_t welch_segment_count(std::int64_t n_samples, std::int64_t segment_length) {
  if (segment_length < 2 || n_samples < segment_length) return 0;
  return (n_samples - segment_length) / (segment_length / 2) + 1;
}

std::int64_t welch_segment_length(std::int64_t n_samples, std::int64_t min_segments) {
  if (min_segments < 1)
    throw std::invalid_argument("welch_segment_length: min_segments must be >= 1, got " +
                                std::to_string(min_segments));
  if (welch_segment_count(n_samples, kMinSegment) < min_segments)
    throw std::invalid_argument("welch_segment_length: n_samples = " + std::to_string(n_samples) +
                                " is too short for " + std::to_string(min_segments) +
                                " segments of " + std::to_string(kMinSegment) + " samples");
  std::int64_t L = kMinSegment;
  while (2 * L <= kMaxSegment / 2 && welch_segment_count(n_samples, 2 * L) >= min_segments)
    L *= 2;
  return L;
}

// ---------------------------------------------------------------------------------------------

struct PsdPlan::Impl {
  std::int64_t L = 0;
  std::int64_t n_bins = 0;  // L/2 + 1
  std::vector<double> window;
  double sum_w2 = 0;  // sum_t w_t^2, the window power of the normalization
  double rho = 0;     // overlap correlation of the window at the 50 % hop (edf)
  std::optional<fft::Plan> plan;
  bool from_wisdom = false;  // the plan came from the stored wisdom (fft.hpp r2c_stored)
};

PsdPlan::PsdPlan(std::int64_t segment_length) : impl_(std::make_unique<Impl>()) {
  if (segment_length < kMinSegment || segment_length % 2 != 0 || segment_length >= kMaxSegment)
    throw std::invalid_argument("PsdPlan: segment_length must be even, >= 16 and < 2^30, got " +
                                std::to_string(segment_length));
  auto& d = *impl_;
  d.L = segment_length;
  d.n_bins = d.L / 2 + 1;
  const auto Ls = static_cast<std::size_t>(d.L);
  d.window.resize(Ls);
  // Periodic ("DFT-even") Hann: its DFT has exactly three non-zero terms (1/2, -1/4, -1/4),
  // so the leakage into neighbouring bins, their correlations and the 50 % overlap-add are
  // exact rational numbers (Harris, Proc. IEEE 66(1), 1978, sec. IV).
  for (std::size_t t = 0; t < Ls; ++t)
    d.window[t] = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * static_cast<double>(t) /
                                       static_cast<double>(d.L));
  double s11 = 0;
  for (std::size_t t = 0; t < Ls; ++t) {
    d.sum_w2 += d.window[t] * d.window[t];
    if (t + Ls / 2 < Ls) s11 += d.window[t] * d.window[t + Ls / 2];
  }
  // Correlation of the periodograms of two overlapping segments of white noise is rho^2
  // (Percival & Walden eq. (292b)); 1/6 for Hann at 50 % overlap (Harris 1978, Table 1).
  d.rho = s11 / d.sum_w2;

  // One segment a transform, planned from the stored wisdom (FFTW_MEASURE's choice, measured
  // once: 2.0x faster than FFTW_ESTIMATE's at 2^18 on this project's machine kind, where a batch
  // of four segments a plan was 1.4x slower than one) and so the same in every run; the
  // per-thread buffers of welch() come from fft::alloc like these, so the plan's SIMD
  // alignment holds for them.
  auto in = fft::alloc<double>(Ls);
  auto out = fft::alloc<fftw_complex>(static_cast<std::size_t>(d.n_bins));
  d.plan.emplace(
      fft::Plan::r2c_stored(static_cast<int>(d.L), in.get(), out.get(), "PsdPlan", &d.from_wisdom));
}

PsdPlan::~PsdPlan() = default;

const PsdPlan& PsdPlan::shared(std::int64_t segment_length) {
  static std::mutex mutex;
  // Never destroyed: a plan's destructor takes FFTW's planner lock, which may be gone by the
  // time static objects are destroyed at exit.
  static auto* plans = new std::map<std::int64_t, std::unique_ptr<PsdPlan>>();
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<PsdPlan>& plan = (*plans)[segment_length];
  if (!plan) plan = std::make_unique<PsdPlan>(segment_length);
  return *plan;
}

bool PsdPlan::from_wisdom() const {
  return impl_->from_wisdom;
}

std::int64_t PsdPlan::segment_length() const {
  return impl_->L;
}

PsdResult PsdPlan::welch(std::span<const double> rate, double rate_hz, int nthreads) const {
  const auto& d = *impl_;
  check_rate(rate_hz, "welch");
  const auto n = static_cast<std::int64_t>(rate.size());
  if (n < d.L)
    throw std::invalid_argument("welch: rate has " + std::to_string(n) +
                                " samples, fewer than the segment length " + std::to_string(d.L));
  // Sanity check at entry (no throw inside the parallel region): infinities are errors, NaN
  // are gaps, remembered by position (a gap-free record stores nothing).
  std::vector<std::int64_t> nan_at;
  for (std::int64_t i = 0; i < n; ++i) {
    const double v = rate[static_cast<std::size_t>(i)];
    if (std::isinf(v))
      throw std::invalid_argument("welch: rate has an infinite sample at index " +
                                  std::to_string(i));
    if (std::isnan(v)) nan_at.push_back(i);
  }
  const std::int64_t hop = d.L / 2;
  const std::int64_t n_all = welch_segment_count(n, d.L);
  std::vector<std::int64_t> starts;
  for (std::int64_t j = 0; j < n_all; ++j) {
    const std::int64_t s = j * hop;
    const auto first_nan = std::lower_bound(nan_at.begin(), nan_at.end(), s);
    if (first_nan == nan_at.end() || *first_nan >= s + d.L) starts.push_back(s);
  }
  const auto n_seg = static_cast<std::int64_t>(starts.size());
  if (n_seg == 0)
    throw std::invalid_argument("welch: rate has no gap-free segment of " + std::to_string(d.L) +
                                " samples (every segment touches a NaN)");

  // Rounds of one segment per thread: each segment's |X_k|^2 row goes to its own slot, then the
  // round's rows are added to acc in segment order. acc is thus the same sequential sum over
  // segments for any thread count, and only one round of rows is held (2^17 bins x threads)
  // instead of every segment's (40 x 2^17 doubles, the size of the record).
  const auto nb = d.n_bins;
  [[maybe_unused]] const int nt = resolve_threads(nthreads);
  const std::int64_t per_round = std::max<std::int64_t>(1, std::min<std::int64_t>(nt, n_seg));
  std::vector<double> acc(static_cast<std::size_t>(nb), 0.0);
  LargeVector<double> rows(static_cast<std::size_t>(per_round * nb));  // each written before use
  std::vector<fft::Buffer<double>> in(static_cast<std::size_t>(per_round));
  std::vector<fft::Buffer<fftw_complex>> out(static_cast<std::size_t>(per_round));
  for (std::int64_t t = 0; t < per_round; ++t) {
    in[static_cast<std::size_t>(t)] = fft::alloc<double>(static_cast<std::size_t>(d.L));
    out[static_cast<std::size_t>(t)] = fft::alloc<fftw_complex>(static_cast<std::size_t>(nb));
  }
  for (std::int64_t r0 = 0; r0 < n_seg; r0 += per_round) {
    const std::int64_t r1 = std::min(n_seg, r0 + per_round);
#pragma omp parallel for num_threads(nt) schedule(static, 1)
    for (std::int64_t s = r0; s < r1; ++s) {
      double* seg = in[static_cast<std::size_t>(s - r0)].get();
      fftw_complex* X = out[static_cast<std::size_t>(s - r0)].get();
      const double* y = rate.data() + starts[static_cast<std::size_t>(s)];
      double sum = 0;
      for (std::int64_t t = 0; t < d.L; ++t)
        sum += y[t];
      const double mean = sum / static_cast<double>(d.L);
      for (std::int64_t t = 0; t < d.L; ++t)
        seg[t] = (y[t] - mean) * d.window[static_cast<std::size_t>(t)];
      d.plan->execute_r2c(seg, X);
      double* row = rows.data() + (s - r0) * nb;
      for (std::int64_t k = 0; k < nb; ++k)
        row[k] = X[k][0] * X[k][0] + X[k][1] * X[k][1];
    }
#pragma omp parallel for num_threads(nt) schedule(static)
    for (std::int64_t k = 0; k < nb; ++k)
      for (std::int64_t s = r0; s < r1; ++s)
        acc[static_cast<std::size_t>(k)] += rows[static_cast<std::size_t>((s - r0) * nb + k)];
  }

  PsdResult r;
  r.rate_hz = rate_hz;
  r.segment_length = d.L;
  r.df_hz = rate_hz / static_cast<double>(d.L);
  r.n_segments = n_seg;
  r.n_skipped = n_all - n_seg;
  r.f_hz.resize(static_cast<std::size_t>(nb));
  r.psd.resize(static_cast<std::size_t>(nb));
  r.edf.resize(static_cast<std::size_t>(nb));
  // Normalization: |X_k|^2 / (rate_hz sum w^2) is the two-sided density of the windowed
  // segment (sum over all L bins times df = rate_hz / L gives sum (w y)^2 / sum w^2); x2
  // folds the negative frequencies in, except at DC and Nyquist, which have no mirror.
  const double base = 1.0 / (rate_hz * d.sum_w2 * static_cast<double>(n_seg));
  for (std::int64_t k = 0; k < nb; ++k) {
    const double c = (k == 0 || k == nb - 1) ? 1.0 : 2.0;
    r.psd[static_cast<std::size_t>(k)] = c * base * acc[static_cast<std::size_t>(k)];
    r.f_hz[static_cast<std::size_t>(k)] = static_cast<double>(k) * r.df_hz;
  }
  std::int64_t n_adj = 0;
  for (std::size_t s = 1; s < starts.size(); ++s)
    if (starts[s] - starts[s - 1] == hop) ++n_adj;
  const double ns = static_cast<double>(n_seg);
  const double edf = 2 * ns * ns / (ns + 2 * d.rho * d.rho * static_cast<double>(n_adj));
  std::fill(r.edf.begin(), r.edf.end(), edf);
  r.edf.front() = edf / 2;
  r.edf.back() = edf / 2;
  return r;
}

PsdResult welch_psd(std::span<const double> rate, double rate_hz, int nthreads,
                    std::int64_t min_segments) {
  check_rate(rate_hz, "welch");
  const PsdPlan& plan =
      PsdPlan::shared(welch_segment_length(static_cast<std::int64_t>(rate.size()), min_segments));
  return plan.welch(rate, rate_hz, nthreads);
}

// ---------------------------------------------------------------------------------------------

BinnedPsd log_bin(const PsdResult& p, int bins_per_decade, int n_linear) {
  if (bins_per_decade < 1)
    throw std::invalid_argument("log_bin: bins_per_decade must be >= 1, got " +
                                std::to_string(bins_per_decade));
  if (n_linear < 0)
    throw std::invalid_argument("log_bin: n_linear must be >= 0, got " + std::to_string(n_linear));
  if (p.psd.size() != p.f_hz.size() || p.edf.size() != p.f_hz.size() || p.size() < 2 ||
      p.segment_length < 2)
    throw std::invalid_argument("log_bin: psd is not a Welch result (sizes disagree)");
  // Correlation of periodogram bins d apart for a locally white spectrum, from the window
  // (Percival & Walden sec. 6.6): r_d = |sum w^2 e^{-2 pi i d t / L}|^2 / (sum w^2)^2. For the
  // periodic Hann, w^2 = 3/8 - cos(2 pi t/L)/2 + cos(4 pi t/L)/8 has exactly three DFT lines,
  // so r_1 = ((1/4) / (3/8))^2 = 4/9, r_2 = ((1/16) / (3/8))^2 = 1/36 and r_d = 0 beyond, for
  // every L >= 8 (checked against the direct sum in test_psd.cpp).
  constexpr int kMaxLag = 2;
  constexpr double r[kMaxLag + 1] = {1.0, 4.0 / 9.0, 1.0 / 36.0};
  auto edf_of_mean = [&](double nu, std::int64_t cnt) {
    const double c = static_cast<double>(cnt);
    double den = c;
    for (int dl = 1; dl <= kMaxLag && dl < cnt; ++dl)
      den += 2 * static_cast<double>(cnt - dl) * r[dl];
    return nu * c * c / den;
  };

  BinnedPsd out;
  const auto nb = static_cast<std::int64_t>(p.size());
  std::int64_t k = 1;
  for (; k < nb && k <= n_linear; ++k) {
    out.f_hz.push_back(p.f_hz[static_cast<std::size_t>(k)]);
    out.psd.push_back(p.psd[static_cast<std::size_t>(k)]);
    out.n_avg.push_back(1);
    out.edf.push_back(p.edf[static_cast<std::size_t>(k)]);
  }
  const double K = bins_per_decade;
  while (k < nb) {
    // The log bin holding f_k: [10^(i/K), 10^((i+1)/K)).
    const double f0 = p.f_hz[static_cast<std::size_t>(k)];
    const double i = std::floor(std::log10(f0) * K + 1e-12);
    const double f_hi = std::pow(10.0, (i + 1) / K);
    double sf = 0, sp = 0, nu = 0;
    std::int64_t cnt = 0;
    for (; k < nb && p.f_hz[static_cast<std::size_t>(k)] < f_hi * (1 - 1e-12); ++k, ++cnt) {
      sf += p.f_hz[static_cast<std::size_t>(k)];
      sp += p.psd[static_cast<std::size_t>(k)];
      nu = std::min(nu == 0 ? p.edf[static_cast<std::size_t>(k)] : nu,
                    p.edf[static_cast<std::size_t>(k)]);
    }
    if (cnt == 0) {  // rounding put f_k on the upper edge: take it alone
      sf = p.f_hz[static_cast<std::size_t>(k)];
      sp = p.psd[static_cast<std::size_t>(k)];
      nu = p.edf[static_cast<std::size_t>(k)];
      cnt = 1;
      ++k;
    }
    out.f_hz.push_back(sf / static_cast<double>(cnt));
    out.psd.push_back(sp / static_cast<double>(cnt));
    out.n_avg.push_back(cnt);
    out.edf.push_back(edf_of_mean(nu, cnt));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

double allan_kernel_discrete(double f_hz, double tau_s, double rate_hz) {
  const double x = std::numbers::pi * f_hz / rate_hz;  // pi f tau0
  const double m = tau_s * rate_hz;
  const double u = std::numbers::pi * f_hz * tau_s;  // pi f tau = m x
  if (x < 1e-9) return 2 * u * u;                    // both sines in their linear range
  const double s = std::sin(u);
  const double d = m * std::sin(x);
  return 2 * (s * s) * (s * s) / (d * d);
}

namespace {

// integral_0^{fl} A f^a |H(f, tau)|^2 df for a > -3: analytic below f_min (where
// |H|^2 = 2 (pi f tau)^2 to a relative 1e-6), composite Simpson in s = ln f above, with a step
// resolving the kernel's oscillation (period 1/(f tau) in s) by >= 20 points at f = fl.
double low_integral(double A, double a, double fl, double tau, double rate_hz) {
  const double f_min = std::min(fl, 1e-3 / (std::numbers::pi * tau));
  const double c = 2 * std::numbers::pi * std::numbers::pi * tau * tau;
  double total = c * A * std::pow(f_min, a + 3) / (a + 3);
  if (f_min >= fl) return total;
  const double span = std::log(fl / f_min);
  const double h_max = std::min(0.02, 0.05 / (fl * tau));
  auto steps = static_cast<std::int64_t>(std::ceil(span / h_max));
  // The cap binds only for fl tau > ~2000, i.e. tau hundreds of times beyond the valid range
  // (fl tau <= 1.5 max_m_fraction there); such a tau is invalid and its value only indicative.
  steps = std::clamp<std::int64_t>(steps + (steps % 2), 2, std::int64_t{1} << 20);
  const double h = span / static_cast<double>(steps);
  const double ls = std::log(f_min);
  auto g = [&](std::int64_t i) {
    const double f = std::exp(ls + h * static_cast<double>(i));
    return A * std::pow(f, a + 1) * allan_kernel_discrete(f, tau, rate_hz);
  };
  double acc = g(0) + g(steps);
  for (std::int64_t i = 1; i < steps; ++i)
    acc += (i % 2 ? 4.0 : 2.0) * g(i);
  return total + acc * h / 3;
}

// The preconditions of avar_from_psd (std::invalid_argument naming the option or tau).
void check_avar_inputs(const PsdResult& p, std::span<const double> tau_s,
                       const AvarPsdOptions& opt) {
  check_rate(p.rate_hz, "avar_from_psd");
  const auto nb = static_cast<std::int64_t>(p.size());
  if (p.psd.size() != p.f_hz.size() || p.edf.size() != p.f_hz.size() ||
      p.segment_length / 2 + 1 != nb || !(p.df_hz > 0))
    throw std::invalid_argument("avar_from_psd: psd is not a Welch result (sizes disagree)");
  if (opt.first_bin < 1 || opt.first_bin + 2 >= nb)
    throw std::invalid_argument("avar_from_psd: opt.first_bin must be >= 1 and leave >= 2 bins, "
                                "got " +
                                std::to_string(opt.first_bin));
  if (!(opt.max_low_fraction >= 0 && opt.max_low_fraction <= 1))
    throw std::invalid_argument("avar_from_psd: opt.max_low_fraction must be in [0, 1], got " +
                                num(opt.max_low_fraction));
  if (!(opt.max_m_fraction > 0) || !std::isfinite(opt.max_m_fraction))
    throw std::invalid_argument("avar_from_psd: opt.max_m_fraction must be > 0, got " +
                                num(opt.max_m_fraction));
  if (!(opt.fit_decades > 0) || !std::isfinite(opt.fit_decades))
    throw std::invalid_argument("avar_from_psd: opt.fit_decades must be > 0, got " +
                                num(opt.fit_decades));
  const double tau0 = 1.0 / p.rate_hz;
  for (std::size_t i = 0; i < tau_s.size(); ++i)
    if (!std::isfinite(tau_s[i]) || tau_s[i] < tau0 * (1 - 1e-12))
      throw std::invalid_argument("avar_from_psd: tau_s[" + std::to_string(i) +
                                  "] must be finite and >= 1/rate_hz = " + num(tau0) + ", got " +
                                  num(tau_s[i]));
}

// Power law A f^a through the lowest fit_decades of the band: least squares on
// ln psd_k + 1/edf_k (E ln(chi2_nu / nu) = -1/nu + O(nu^-2) is the log bias of an average).
// Fills low_exponent, low_coefficient and low_fit_ok of r.
void fit_low_power_law(const PsdResult& p, const AvarPsdOptions& opt, AvarPsdResult& r) {
  const auto nb = static_cast<std::int64_t>(p.size());
  const auto kb = static_cast<std::size_t>(opt.first_bin);
  const auto k_hi = std::min<std::int64_t>(
      nb - 2, static_cast<std::int64_t>(std::floor(static_cast<double>(opt.first_bin) *
                                                   std::pow(10.0, opt.fit_decades))));
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  std::int64_t cnt = 0;
  bool positive = true;
  for (auto k = static_cast<std::int64_t>(kb); k <= k_hi; ++k) {
    const double v = p.psd[static_cast<std::size_t>(k)];
    if (!(v > 0)) positive = false;
    if (!positive) break;
    const double x = std::log(p.f_hz[static_cast<std::size_t>(k)]);
    const double y = std::log(v) + 1.0 / p.edf[static_cast<std::size_t>(k)];
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++cnt;
  }
  const double cn = static_cast<double>(cnt);
  const double det = cn * sxx - sx * sx;
  if (positive && cnt >= 3 && det > 0) {
    r.low_exponent = (cn * sxy - sx * sy) / det;
    r.low_coefficient = std::exp((sy - r.low_exponent * sx) / cn);
    r.low_fit_ok = r.low_exponent > -3 + 1e-6;
  }
}

}  // namespace

AvarPsdResult avar_from_psd(const PsdResult& p, std::span<const double> tau_s,
                            const AvarPsdOptions& opt, int nthreads) {
  check_avar_inputs(p, tau_s, opt);
  const auto nb = static_cast<std::int64_t>(p.size());
  AvarPsdResult r;
  const auto kb = static_cast<std::size_t>(opt.first_bin);
  r.f_low_hz = (static_cast<double>(opt.first_bin) - 0.5) * p.df_hz;

  fit_low_power_law(p, opt, r);

  const std::size_t nt_tau = tau_s.size();
  r.tau_s.assign(tau_s.begin(), tau_s.end());
  r.avar.resize(nt_tau);
  r.avar_band.resize(nt_tau);
  r.avar_low.resize(nt_tau);
  r.valid.resize(nt_tau);
  const double L = static_cast<double>(p.segment_length);
  const std::int64_t Li = p.segment_length;
  // At the Welch bins f_k = k rate_hz / L and an integer m, both sines of the discrete kernel
  // are sin(pi j / L) at integers j: the denominator's at j = k, the numerator's at
  // j = k m mod L (|sin| has period L and is symmetric about L/2). One table of
  // |sin(pi j / L)|, j = 0 .. L/2, and an exact integer argument reduction replace two sin()
  // per bin and tau: about 20x faster, and more accurate at large m than sin(pi f m tau0) of a
  // rounded product. Non-integer m (a tau not on the sample grid) takes the direct formula.
  std::vector<double> sin_tab(static_cast<std::size_t>(Li / 2 + 1));
  for (std::int64_t j = 0; j <= Li / 2; ++j)
    sin_tab[static_cast<std::size_t>(j)] =
        std::sin(std::numbers::pi * static_cast<double>(j) / static_cast<double>(Li));
  // The tau-independent factor of every bin, weight x psd / sin^2(pi k / L), once for all taus:
  // the inner loop then has no division (it was half of this function's time).
  std::vector<double> bin_weight(static_cast<std::size_t>(nb), 0.0);
  for (auto k = static_cast<std::int64_t>(kb); k < nb; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const double sd = sin_tab[ku];
    const double wgt = k == nb - 1 ? 0.5 : 1.0;  // the Nyquist bin's cell is half inside
    bin_weight[ku] = wgt * p.psd[ku] / (sd * sd);
  }
  [[maybe_unused]] const int nt = resolve_threads(nthreads);
#pragma omp parallel for num_threads(nt) schedule(dynamic)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(nt_tau); ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double tau = tau_s[iu];
    const double m_real = tau * p.rate_hz;
    const double m_round = std::round(m_real);
    double band = 0;
    if (std::abs(m_real - m_round) <= 1e-9 * m_round && m_round >= 1) {
      const auto m = static_cast<std::int64_t>(m_round);
      const std::int64_t step = m % Li;
      std::int64_t j = (static_cast<std::int64_t>(kb) * step) % Li;
      // Branch-free index arithmetic (min and a conditional subtraction): j jumps by m mod L
      // and its half of the period is unpredictable for most m.
      for (auto k = static_cast<std::int64_t>(kb); k < nb; ++k) {
        const double sn = sin_tab[static_cast<std::size_t>(std::min(j, Li - j))];
        band += bin_weight[static_cast<std::size_t>(k)] * ((sn * sn) * (sn * sn));
        j += step;
        j -= j >= Li ? Li : 0;
      }
      band *= 2.0 / (m_round * m_round);
    } else {
      for (auto k = static_cast<std::int64_t>(kb); k < nb; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        const double wgt = k == nb - 1 ? 0.5 : 1.0;
        band += wgt * p.psd[ku] * allan_kernel_discrete(p.f_hz[ku], tau, p.rate_hz);
      }
    }
    band *= p.df_hz;
    double low = std::numeric_limits<double>::quiet_NaN();
    if (r.low_fit_ok)
      low = low_integral(r.low_coefficient, r.low_exponent, r.f_low_hz, tau, p.rate_hz);
    r.avar_band[iu] = band;
    r.avar_low[iu] = low;
    r.avar[iu] = r.low_fit_ok ? band + low : band;
    r.valid[iu] = r.low_fit_ok && low <= opt.max_low_fraction * (band + low) &&
                  tau * p.rate_hz <= opt.max_m_fraction * L * (1 + 1e-12);
  }
  r.tau_valid_min = r.tau_valid_max = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < nt_tau; ++i)
    if (r.valid[i]) {
      if (!(r.tau_valid_min <= r.tau_s[i])) r.tau_valid_min = r.tau_s[i];
      if (!(r.tau_valid_max >= r.tau_s[i])) r.tau_valid_max = r.tau_s[i];
    }
  return r;
}

}  // namespace allanlot::kernels
