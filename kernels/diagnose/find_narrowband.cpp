// Diagnose's PSD witness of a narrowband process (docs/diagnose.md "PSD witness"): a
// periodogram peak wider than a line, and its resonance (f0, q, sigma) fitted to the bins around
// it. The Allan curve measures a narrow peak's q poorly: beyond a few hundred the curve of a
// resonance is that of a line at every tau where it matters, so the curve's search ends at the top
// of q's range (the ADIS16405 accelerometers' peak near 0.47-0.57 Hz: q > 4000 on the curve,
// 290-1080 in their periodograms, whose resolution is 1e-4 Hz).
#include "kernels/diagnose/internal.hpp"

#include "kernels/simulate/resonance.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace allanlot::kernels::diagnose_detail {
namespace {

constexpr std::int64_t kNearLo = 4, kNearHi = 32;

// Parameters: ln f0, ln q, ln sigma^2, ln background at the window's centre, and the
// background's log slope across the window.
using Params = std::array<double, 5>;

// Whittle's likelihood (a periodogram bin is its spectrum times an exponential variate: Whittle
// 1953) of the means of `block` adjacent bins over a window, under a log-linear background plus
// a resonance's one-sided PSD. The mean of B bins is Gamma(B, S / B), so the negative
// log-likelihood is B sum (ln S + P / S).
struct Whittle {
  double rate_hz = 0.0;
  double block = 1.0;
  std::vector<double> f, p;  // the blocks' centre frequencies and mean periodogram
  double f_mid = 0.0, f_span = 1.0;

  Whittle(const PsdResult& psd, std::int64_t k0, std::int64_t k1, std::int64_t b)
      : rate_hz(2.0 * static_cast<double>(psd.size() - 1) * psd.df_hz),
        block(static_cast<double>(b)) {
    for (std::int64_t k = k0; k + b - 1 <= k1; k += b) {
      double sum = 0.0;
      for (std::int64_t j = k; j < k + b; ++j)
        sum += psd.psd[static_cast<std::size_t>(j)];
      f.push_back((static_cast<double>(k) + 0.5 * static_cast<double>(b - 1)) * psd.df_hz);
      p.push_back(sum / block);
    }
    if (!f.empty()) {
      f_mid = 0.5 * (f.front() + f.back());
      f_span = std::max(f.back() - f.front(), psd.df_hz);
    }
  }
  std::vector<double> ln_spectrum(const Params& x) const {
    const Resonance unit{1.0, std::exp(x[0]), std::exp(x[1])};
    std::vector<double> out(f.size());
    for (std::size_t j = 0; j < f.size(); ++j) {
      const double bg = std::exp(x[3] + x[4] * (f[j] - f_mid) / f_span);
      const double res =
          x[2] > -600.0 ? std::exp(x[2]) * resonance_psd_one_sided(unit, rate_hz, f[j]) : 0.0;
      out[j] = std::log(bg + res);
    }
    return out;
  }
  bool valid(const Params& x) const {
    const double f0 = std::exp(x[0]), q = std::exp(x[1]);
    return f0 > 0.0 && f0 < 0.5 * rate_hz && q >= kResonanceMinQ && q <= kResonanceMaxQ &&
           std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
  }
  double nll(const Params& x) const {
    if (!valid(x)) return std::numeric_limits<double>::infinity();
    const std::vector<double> ls = ln_spectrum(x);
    double s = 0.0;
    for (std::size_t j = 0; j < f.size(); ++j)
      s += ls[j] + p[j] * std::exp(-ls[j]);
    return block * s;
  }
  // d ln S_j / d x_a of the parameters `free`, by central differences.
  Eigen::MatrixXd jacobian(const Params& x, const std::vector<std::size_t>& free) const {
    Eigen::MatrixXd jac(static_cast<Eigen::Index>(f.size()),
                        static_cast<Eigen::Index>(free.size()));
    for (std::size_t a = 0; a < free.size(); ++a) {
      Params lo = x, hi = x;
      lo[free[a]] -= 1e-6;
      hi[free[a]] += 1e-6;
      const std::vector<double> sl = ln_spectrum(lo), sh = ln_spectrum(hi);
      for (std::size_t j = 0; j < f.size(); ++j)
        jac(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(a)) = (sh[j] - sl[j]) / 2e-6;
    }
    return jac;
  }
};

// Fisher scoring of the parameters `free` from x (the step I^-1 J^T (P / S - 1) with
// I = J^T J, halved until the likelihood improves); the minimum found and its negative
// log-likelihood.
std::pair<Params, double> score(const Whittle& w, Params x, const std::vector<std::size_t>& free) {
  double now = w.nll(x);
  for (int it = 0; it < 60 && std::isfinite(now); ++it) {
    const Eigen::MatrixXd jac = w.jacobian(x, free);
    const std::vector<double> ls = w.ln_spectrum(x);
    Eigen::VectorXd r(jac.rows());
    for (Eigen::Index j = 0; j < r.size(); ++j)
      r(j) = w.p[static_cast<std::size_t>(j)] * std::exp(-ls[static_cast<std::size_t>(j)]) - 1.0;
    const Eigen::VectorXd step = (jac.transpose() * jac).ldlt().solve(jac.transpose() * r);
    double scale = 1.0;
    bool moved = false;
    for (int h = 0; h < 30 && !moved; ++h, scale *= 0.5) {
      Params y = x;
      for (std::size_t a = 0; a < free.size(); ++a)
        y[free[a]] += scale * step(static_cast<Eigen::Index>(a));
      if (const double v = w.nll(y); v < now) {
        moved = now - v > 1e-9;
        x = y;
        now = v;
      }
    }
    if (!moved) break;
  }
  return {x, now};
}

// The Hann window's correlation of neighbouring bins' powers (|2/3|^2 and |1/6|^2 at one and two
// bins) makes a sum over bins vary 1 + 2 (4/9 + 1/36) times as much as over independent ones:
// the Fisher information and the likelihood ratio are divided by it.
constexpr double kHannInflation = 1.0 + 2.0 * (4.0 / 9.0 + 1.0 / 36.0);

// The resonance over the window k0 .. k1 in blocks of `block` bins: Fisher scoring from f0 =
// f_start with q from q_starts and sigma^2 from the window's excess at the start's peak, the
// best likelihood kept. Found when q lies strictly inside (2, f0 over two blocks) and the
// resonance's likelihood ratio against the background alone passes the chi-square quantile of
// 3 degrees of freedom at false_alarm.
SpectralLine::Narrowband fit_window(const PsdResult& psd, std::int64_t k0, std::int64_t k1,
                                    std::int64_t block, double f_start,
                                    const std::vector<double>& q_starts, double false_alarm) {
  SpectralLine::Narrowband out;
  const Whittle w(psd, k0, k1, block);
  if (w.f.size() < 16) return out;
  std::vector<double> sorted = w.p;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 4),
                   sorted.end());
  const double bg = sorted[sorted.size() / 4];
  const double top = *std::max_element(w.p.begin(), w.p.end());
  const std::vector<std::size_t> all{0, 1, 2, 3, 4}, background{3, 4};
  std::pair<Params, double> best{{}, std::numeric_limits<double>::infinity()};
  for (const double q : q_starts) {
    // At its peak a resonance's PSD is about 2 sigma^2 q / (pi f0) (a Lorentzian of half-width
    // f0 / (2 q) holding sigma^2).
    const double s2 = std::max(top - bg, bg) * std::numbers::pi * f_start / (2.0 * q);
    const auto r = score(w, {std::log(f_start), std::log(q), std::log(s2), std::log(bg), 0.0}, all);
    if (r.second < best.second) best = r;
  }
  const auto none = score(w, {std::log(f_start), 0.0, -1000.0, std::log(bg), 0.0}, background);
  if (!std::isfinite(best.second) || !std::isfinite(none.second)) return out;
  const Params& x = best.first;
  const double f0 = std::exp(x[0]), q = std::exp(x[1]);
  const double ratio = 2.0 * (none.second - best.second) / kHannInflation;
  if (!(q > 2.0 && q < f0 / (2.0 * w.block * psd.df_hz)) ||
      ratio < chi2_quantile(1.0 - false_alarm, 3.0))
    return out;
  const Eigen::MatrixXd jac = w.jacobian(x, all);
  const Eigen::MatrixXd cov = (jac.transpose() * jac).inverse() * kHannInflation / w.block;
  if (!cov.allFinite() || cov.diagonal().minCoeff() < 0.0) return out;
  out.found = true;
  out.frequency_hz = f0;
  out.frequency_sigma = f0 * std::sqrt(cov(0, 0));
  out.q = q;
  out.q_sigma = q * std::sqrt(cov(1, 1));
  out.sigma = std::exp(0.5 * x[2]);
  out.sigma_sigma = 0.5 * out.sigma * std::sqrt(cov(2, 2));
  return out;
}

}  // namespace

// Both rings are symmetric about k, so on a locally monotone background each median is the
// central value and their ratio is about 1. The median of M exponential bins has a relative sd
// of about 1.44 / sqrt(M) (the asymptotic variance 1 / (4 M p(median)^2) of a sample median),
// and the Hann window's correlation of neighbouring bins (2/3 and 1/6 at one and two bins)
// about doubles its variance, so for the near ring (58 bins) against the far (578) ln(ratio) has
// an sd of about 0.29, and a ratio above 4 is about 5 sd: a width, not chance.
bool wider_than_a_line(const PsdResult& psd, std::int64_t k) {
  constexpr double kWideRatio = 4.0;
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  if (k - kFarRing < 1 || k + kFarRing > kmax) return false;
  std::vector<double> buf;
  const double near = ring_median(psd, k, kNearLo, kNearHi, buf);
  const double far = ring_median(psd, k, kFarRing / 4, kFarRing, buf);
  return far > 0.0 && near > kWideRatio * far;
}

// The bins of the far ring around the peak, one by one, with q for half-power widths of 2, 4,
// .. 256 bins.
SpectralLine::Narrowband fit_narrowband(const PsdResult& psd, std::int64_t k, double false_alarm) {
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  const double f_peak = static_cast<double>(k) * psd.df_hz;
  std::vector<double> q_starts;
  for (double width = 2.0; width <= 256.0; width *= 2.0)
    if (const double q = f_peak / (width * psd.df_hz); q > 2.0 && q < kResonanceMaxQ)
      q_starts.push_back(q);
  return fit_window(psd, std::max<std::int64_t>(k - kFarRing, 1), std::min(k + kFarRing, kmax - 1),
                    1, f_peak, q_starts, false_alarm);
}

// From half to 1.5 times f0 (below 0.45 of the rate), in blocks that leave about 512 points,
// with q from 2 to 256 by factors of 2.
SpectralLine::Narrowband fit_broad(const PsdResult& psd, double f0, double false_alarm) {
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  const double rate_hz = 2.0 * static_cast<double>(kmax) * psd.df_hz;
  const auto k0 = std::max<std::int64_t>(static_cast<std::int64_t>(0.5 * f0 / psd.df_hz), 1);
  const auto k1 =
      std::min(static_cast<std::int64_t>(std::min(1.5 * f0, 0.45 * rate_hz) / psd.df_hz), kmax - 1);
  const std::int64_t block = std::max<std::int64_t>((k1 - k0) / 512, 1);
  return fit_window(psd, k0, k1, block, f0, {2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0},
                    false_alarm);
}

}  // namespace allanlot::kernels::diagnose_detail
