// Diagnose's PSD witness of a narrowband process (docs/diagnose.md "Witnesses beside the Allan
// curve"): a periodogram peak wider than a line, and its resonance (f0, q, sigma) fitted to the
// bins around it. The Allan curve measures a narrow peak's q poorly: beyond a few hundred the curve
// of a resonance is that of a line at every tau where it matters, so the curve's search ends at the
// top of q's range (the ADIS16405 accelerometers' peak near 0.47-0.57 Hz: q > 4000 on the curve,
// 290-1080 in their periodograms, whose resolution is 1e-4 Hz). The resonance candidate's peak
// is measured here too (fit_peak_shapes: with the model's resonances beside it, wandering where
// significant), and a wandering resonance's correlation time on its frequency's track.
#include "kernels/diagnose/internal.hpp"

#include "kernels/simulate/resonance.hpp"
#include "kernels/spectral/psd.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace allanlot::kernels::diagnose_detail {
namespace {

constexpr std::int64_t kNearLo = 4, kNearHi = 32;

// The parameters of a fit: the background's ln level at the window's centre and its log slope
// across the window, then for each resonance ln f0, ln q, ln sigma^2 and, for a wandering one
// (kernels/simulate/resonance.hpp), ln spread.
using Params = std::vector<double>;
constexpr std::size_t kBackground = 2;

// Where each resonance's parameters start in a Params, by which of them wander.
struct Layout {
  std::vector<bool> wander;
  std::vector<std::size_t> at;
  explicit Layout(std::vector<bool> w) : wander(std::move(w)) {
    std::size_t i = kBackground;
    for (const bool b : wander) {
      at.push_back(i);
      i += b ? 4 : 3;
    }
  }
  std::size_t count() const { return wander.size(); }
  Resonance unit(const Params& x, std::size_t r) const {
    const std::size_t i = at[r];
    return {1.0, std::exp(x[i]), std::exp(x[i + 1]), wander[r] ? std::exp(x[i + 3]) : 0.0};
  }
};

// Whittle's likelihood (a periodogram bin is its spectrum times an exponential variate: Whittle
// 1953) of the means of `block` adjacent bins over a window, under a log-linear background plus
// resonances' one-sided PSDs. The mean of B bins is Gamma(B, S / B), so the negative
// log-likelihood is B sum (ln S + P / S).
struct Whittle {
  double rate_hz = 0.0;
  double block = 1.0;
  std::vector<double> f, p;  // the blocks' centre frequencies and mean periodogram
  double f_mid = 0.0, f_span = 1.0;
  double df_hz = 0.0;
  PsdTrig trig{{}, 1.0};  // of f, for the many evaluations of the spectrum

  Whittle(const PsdResult& psd, std::int64_t k0, std::int64_t k1, std::int64_t b)
      : rate_hz(psd_rate_hz(psd)), block(static_cast<double>(b)), df_hz(psd.df_hz) {
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
    trig = PsdTrig(f, rate_hz);
  }
  // The largest q whose peak the blocks resolve at f0: half-power width f0 / q over two blocks.
  double q_top(double f0) const { return f0 / (2.0 * block * df_hz); }
  std::vector<double> ln_spectrum(const Layout& l, const Params& x) const {
    std::vector<double> s(f.size());
    for (std::size_t j = 0; j < f.size(); ++j)
      s[j] = std::exp(x[0] + x[1] * (f[j] - f_mid) / f_span);
    for (std::size_t r = 0; r < l.count(); ++r)
      add_resonance_psd(l.unit(x, r), rate_hz, std::exp(x[l.at[r] + 2]), trig, s);
    for (double& v : s)
      v = std::log(v);
    return s;
  }
  bool valid(const Layout& l, const Params& x) const {
    if (!std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); })) return false;
    for (std::size_t r = 0; r < l.count(); ++r) {
      const Resonance u = l.unit(x, r);
      if (!(u.frequency_hz > 0.0 && u.frequency_hz < 0.5 * rate_hz && u.q >= kResonanceMinQ &&
            u.q <= kResonanceMaxQ && u.spread_hz <= resonance_max_spread(u.frequency_hz, rate_hz)))
        return false;
    }
    return true;
  }
  double nll(const Layout& l, const Params& x) const {
    if (!valid(l, x)) return std::numeric_limits<double>::infinity();
    const std::vector<double> ls = ln_spectrum(l, x);
    double s = 0.0;
    for (std::size_t j = 0; j < f.size(); ++j)
      s += ls[j] + p[j] * std::exp(-ls[j]);
    return block * s;
  }
  // d ln S_j / d x_a of every parameter, by central differences. A parameter moves one part of
  // the spectrum (the background, or one resonance), so each difference recomputes that part
  // alone beside the others' sum: the spectrum's resonances evaluated 2 + count times instead
  // of 2 x (parameters) x count (this Jacobian was a tenth of a modelled accelerometer's time).
  Eigen::MatrixXd jacobian(const Layout& l, const Params& x) const {
    Eigen::MatrixXd jac(static_cast<Eigen::Index>(f.size()), static_cast<Eigen::Index>(x.size()));
    const auto background = [&](const Params& y) {
      std::vector<double> s(f.size());
      for (std::size_t j = 0; j < f.size(); ++j)
        s[j] = std::exp(y[0] + y[1] * (f[j] - f_mid) / f_span);
      return s;
    };
    const auto resonance = [&](const Params& y, std::size_t r) {
      std::vector<double> s(f.size(), 0.0);
      add_resonance_psd(l.unit(y, r), rate_hz, std::exp(y[l.at[r] + 2]), trig, s);
      return s;
    };
    std::vector<std::vector<double>> part{background(x)};
    for (std::size_t r = 0; r < l.count(); ++r)
      part.push_back(resonance(x, r));
    const auto column = [&](std::size_t a, std::size_t which, const std::vector<double>& lo,
                            const std::vector<double>& hi) {
      for (std::size_t j = 0; j < f.size(); ++j) {
        double rest = 0.0;
        for (std::size_t q = 0; q < part.size(); ++q)
          if (q != which) rest += part[q][j];
        jac(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(a)) =
            (std::log(rest + hi[j]) - std::log(rest + lo[j])) / 2e-6;
      }
    };
    for (std::size_t a = 0; a < x.size(); ++a) {
      Params lo = x, hi = x;
      lo[a] -= 1e-6;
      hi[a] += 1e-6;
      std::size_t which = 0;  // the background's parameters come first
      for (std::size_t r = 0; r < l.count(); ++r)
        if (a >= l.at[r]) which = r + 1;
      if (which == 0)
        column(a, 0, background(lo), background(hi));
      else
        column(a, which, resonance(lo, which - 1), resonance(hi, which - 1));
    }
    return jac;
  }
};

// Fisher scoring of every parameter from x (the step I^-1 J^T (P / S - 1) with I = J^T J, halved
// until the likelihood improves) under layout l; the minimum found and its negative
// log-likelihood. No parameter moves by more than 1 (a factor e) in one step: where the
// likelihood is flat in a direction, I is nearly singular there and the step is huge. A
// wandering peak's ln spread went to -2.6e6 in one step once a pedestal was fitted beside it,
// the spread's column of J vanished and the fit had no covariance (its shapes none): the
// pedestal was lost on 7 of 40 simulated records of a z gyroscope's peak, and on none with
// the steps bounded (tests/kernels/test_find_narrowband.cpp).
std::pair<Params, double> score(const Whittle& w, const Layout& l, Params x) {
  constexpr double kMaxStep = 1.0;
  double now = w.nll(l, x);
  for (int it = 0; it < 60 && std::isfinite(now); ++it) {
    const Eigen::MatrixXd jac = w.jacobian(l, x);
    const std::vector<double> ls = w.ln_spectrum(l, x);
    Eigen::VectorXd r(jac.rows());
    for (Eigen::Index j = 0; j < r.size(); ++j)
      r(j) = w.p[static_cast<std::size_t>(j)] * std::exp(-ls[static_cast<std::size_t>(j)]) - 1.0;
    const Eigen::VectorXd step = (jac.transpose() * jac).ldlt().solve(jac.transpose() * r);
    double scale = std::min(1.0, kMaxStep / step.cwiseAbs().maxCoeff());
    bool moved = false;
    for (int h = 0; h < 30 && !moved; ++h, scale *= 0.5) {
      Params y = x;
      for (std::size_t a = 0; a < x.size(); ++a)
        y[a] += scale * step(static_cast<Eigen::Index>(a));
      if (const double v = w.nll(l, y); v < now) {
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

// The likelihood ratio statistic of a fit against a nested one, divided by kHannInflation.
double likelihood_ratio(double nll_without, double nll_with) {
  return 2.0 * (nll_without - nll_with) / kHannInflation;
}

// The shapes of a fit's resonances with their 1-sigma, from the inverse Fisher information;
// empty when it is singular.
std::vector<SpectralLine::Narrowband> shapes_of(const Whittle& w, const Layout& l,
                                                const Params& x) {
  const Eigen::MatrixXd jac = w.jacobian(l, x);
  const Eigen::MatrixXd cov = (jac.transpose() * jac).inverse() * kHannInflation / w.block;
  if (!cov.allFinite() || cov.diagonal().minCoeff() < 0.0) return {};
  std::vector<SpectralLine::Narrowband> out;
  for (std::size_t r = 0; r < l.count(); ++r) {
    const auto i = static_cast<Eigen::Index>(l.at[r]);
    const Resonance u = l.unit(x, r);
    SpectralLine::Narrowband nb;
    nb.found = true;
    nb.frequency_hz = u.frequency_hz;
    nb.frequency_sigma = u.frequency_hz * std::sqrt(cov(i, i));
    nb.q = u.q;
    nb.q_sigma = u.q * std::sqrt(cov(i + 1, i + 1));
    nb.sigma = std::exp(0.5 * x[l.at[r] + 2]);
    nb.sigma_sigma = 0.5 * nb.sigma * std::sqrt(cov(i + 2, i + 2));
    if (l.wander[r]) {
      nb.spread_hz = u.spread_hz;
      nb.spread_sigma = u.spread_hz * std::sqrt(cov(i + 3, i + 3));
    }
    out.push_back(nb);
  }
  return out;
}

// The lower quartile of v (reordered): a background beside a peak, which leaves it alone.
double lower_quartile(std::vector<double>& v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 4), v.end());
  return v[v.size() / 4];
}

// The window's background level (its lower quartile) and peak.
std::pair<double, double> background_and_top(const Whittle& w) {
  std::vector<double> sorted = w.p;
  return {lower_quartile(sorted), *std::max_element(w.p.begin(), w.p.end())};
}

// A new resonance's start from its peak's height: at its peak a resonance's PSD is about
// 2 sigma^2 q / (pi f0) (a Lorentzian of half-width f0 / (2 q) holding sigma^2).
void append_start(Params& x, double f0, double q, double height) {
  const double s2 = height * std::numbers::pi * f0 / (2.0 * q);
  x.insert(x.end(), {std::log(f0), std::log(q), std::log(s2)});
}

// The height of a new peak at f0 over the fit x: the window's excess over x's spectrum in the
// block nearest f0, at least that spectrum there (a peak to be found is not below it).
double excess_at(const Whittle& w, const Layout& l, const Params& x, double f0) {
  const std::vector<double> ls = w.ln_spectrum(l, x);
  const auto j = static_cast<std::size_t>(
      std::min_element(w.f.begin(), w.f.end(),
                       [f0](double a, double b) { return std::abs(a - f0) < std::abs(b - f0); }) -
      w.f.begin());
  return std::max(w.p[j] - std::exp(ls[j]), std::exp(ls[j]));
}

// The resonance over the window k0 .. k1 in blocks of `block` bins: Fisher scoring from f0 =
// f_start with q from q_starts and sigma^2 from the window's excess at the start's peak, the
// best likelihood kept. Found when q lies strictly inside (2, f0 over two blocks) and the
// resonance's likelihood ratio against the background alone passes the chi-square quantile of
// 3 degrees of freedom at false_alarm.
SpectralLine::Narrowband fit_window(const PsdResult& psd, std::int64_t k0, std::int64_t k1,
                                    std::int64_t block, double f_start,
                                    const std::vector<double>& q_starts, double false_alarm) {
  const Whittle w(psd, k0, k1, block);
  if (w.f.size() < 16) return {};
  const auto [bg, top] = background_and_top(w);
  const Layout one({false});
  std::pair<Params, double> best{{}, std::numeric_limits<double>::infinity()};
  for (const double q : q_starts) {
    Params x{std::log(bg), 0.0};
    append_start(x, f_start, q, std::max(top - bg, bg));
    const auto r = score(w, one, x);
    if (r.second < best.second) best = r;
  }
  const auto none = score(w, Layout({}), {std::log(bg), 0.0});
  if (!std::isfinite(best.second) || !std::isfinite(none.second)) return {};
  const double f0 = std::exp(best.first[2]), q = std::exp(best.first[3]);
  if (!(q > 2.0 && q < w.q_top(f0)) ||
      likelihood_ratio(none.second, best.second) < chi2_quantile(1.0 - false_alarm, 3.0))
    return {};
  const auto shapes = shapes_of(w, one, best.first);
  return shapes.empty() ? SpectralLine::Narrowband{} : shapes.front();
}

// The new resonance of fit_peak_shapes (last in best's layout), tried wandering too from its
// stationary fit with the spread at its half-width: wandering where the spread's likelihood
// ratio passes chi2(1) at false_alarm, its q still resolved (below f0 over two blocks: narrower,
// the width is the spread's alone and q no estimate) and its spread below 95 % of its range's
// top (above, a band, no peak). Found when its q lies strictly inside (2, f0 over two blocks) and
// its likelihood ratio against the present resonances alone passes chi2 of its 3 or 4 degrees
// of freedom at false_alarm. The present ones' shapes then the new one's, every present one
// outside the window as it was with `found` false; empty when not found.
std::vector<SpectralLine::Narrowband>
accept_new(const Whittle& w, const std::vector<std::size_t>& inside,
           const std::vector<SpectralLine::Narrowband>& present, double nll_none,
           std::pair<Params, double> best, double false_alarm) {
  std::vector<bool> wander(inside.size() + 1, false);
  for (std::size_t j = 0; j < inside.size(); ++j)
    wander[j] = present[inside[j]].spread_hz > 0.0;
  {
    std::vector<bool> with = wander;
    with.back() = true;
    const Layout wandering(with);
    Params x = best.first;
    const double f0 = std::exp(x[x.size() - 3]), q = std::exp(x[x.size() - 2]);
    x.push_back(std::log(std::min(f0 / (2.0 * q), 0.9 * resonance_max_spread(f0, w.rate_hz))));
    const auto r = score(w, wandering, x);
    const Resonance u = wandering.unit(r.first, inside.size());
    if (likelihood_ratio(best.second, r.second) > chi2_quantile(1.0 - false_alarm, 1.0) &&
        u.q < w.q_top(u.frequency_hz) &&
        u.spread_hz < 0.95 * resonance_max_spread(u.frequency_hz, w.rate_hz)) {
      best = r;
      wander = with;
    }
  }
  const Layout chosen(wander);
  const Resonance u = chosen.unit(best.first, inside.size());
  const double dof = wander.back() ? 4.0 : 3.0;
  if (!(u.q > 2.0 && u.q < w.q_top(u.frequency_hz)) ||
      likelihood_ratio(nll_none, best.second) < chi2_quantile(1.0 - false_alarm, dof))
    return {};
  const std::vector<SpectralLine::Narrowband> shapes = shapes_of(w, chosen, best.first);
  if (shapes.empty()) return {};
  std::vector<SpectralLine::Narrowband> out = present;
  for (auto& r : out)
    r.found = false;
  for (std::size_t j = 0; j < inside.size(); ++j)
    out[inside[j]] = shapes[j];
  out.push_back(shapes.back());
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

// From half to 1.5 times f0 (below 0.45 of the rate), in blocks that leave about 512 points.
// The present resonances inside start from their shapes (sigma^2 from the window's excess like a
// new one's); the model without the new one is fitted too, for the likelihood ratio.
std::vector<SpectralLine::Narrowband>
fit_peak_shapes(const PsdResult& psd, const std::vector<SpectralLine::Narrowband>& present,
                double f0, const std::vector<double>& q_starts, double false_alarm) {
  const auto kmax = static_cast<std::int64_t>(psd.size()) - 1;
  const double rate_hz = psd_rate_hz(psd);
  const auto k0 = std::max<std::int64_t>(static_cast<std::int64_t>(0.5 * f0 / psd.df_hz), 1);
  const auto k1 =
      std::min(static_cast<std::int64_t>(std::min(1.5 * f0, 0.45 * rate_hz) / psd.df_hz), kmax - 1);
  const std::int64_t block = std::max<std::int64_t>((k1 - k0) / 512, 1);
  const Whittle w(psd, k0, k1, block);
  if (w.f.size() < 16) return {};
  std::vector<std::size_t> inside;
  std::vector<bool> wander;
  const auto [bg, top] = background_and_top(w);
  Params base{std::log(bg), 0.0};
  for (std::size_t i = 0; i < present.size(); ++i) {
    const SpectralLine::Narrowband& r = present[i];
    if (r.frequency_hz < w.f.front() || r.frequency_hz > w.f.back()) continue;
    inside.push_back(i);
    wander.push_back(r.spread_hz > 0.0);
    append_start(base, r.frequency_hz, r.q, std::max(top - bg, bg));
    if (r.spread_hz > 0.0) base.push_back(std::log(r.spread_hz));
  }
  const Layout without(wander);
  const auto none = score(w, without, base);
  const double height = excess_at(w, without, none.first, f0);
  wander.push_back(false);
  const Layout stationary(wander);
  std::pair<Params, double> best{{}, std::numeric_limits<double>::infinity()};
  for (const double q : q_starts) {
    Params x = none.first;
    append_start(x, f0, q, height);
    const auto r = score(w, stationary, x);
    if (r.second < best.second) best = r;
  }
  if (!std::isfinite(best.second) || !std::isfinite(none.second)) return {};
  return accept_new(w, inside, present, none.second, best, false_alarm);
}

// A broad hump (q of a few to a few tens) raises many bins by a little: no bin stands out for
// the line search, but the band's mean does, by (excess) sqrt(bins / kHannInflation) standard
// deviations (the mean of B exponential variates, neighbours correlated by the Hann window).
// Bands of 1/16 octave resolve a q above about 10; the background, the median of the 16 bands
// within half an octave (itself left out), follows a filter's roll-off and leaves a hump of up
// to a quarter octave alone (the ADIS16405 accelerometers' at 9.5-10 Hz, 20 % over 2 Hz).
std::vector<std::pair<double, double>> broad_peaks(const PsdResult& psd, double f_lo_hz,
                                                   std::size_t count) {
  constexpr int kPerOctave = 16, kHalfOctave = kPerOctave / 2;
  constexpr std::size_t kMinBins = 8;
  struct Band {
    double f = 0.0, mean = 0.0, z = 0.0;
    std::size_t bins = 0;
  };
  std::vector<Band> bands;
  const double f_top = psd_rate_hz(psd) / 2.0;
  std::size_t k = 1;
  for (double lo = std::max(f_lo_hz, psd.df_hz); lo < f_top;) {
    const double hi = lo * std::exp2(1.0 / kPerOctave);
    Band b;
    b.f = std::sqrt(lo * hi);
    for (; k < psd.size() && psd.f_hz[k] < hi; ++k)
      if (psd.f_hz[k] >= lo) {
        b.mean += psd.psd[k];
        ++b.bins;
      }
    if (b.bins > 0) b.mean /= static_cast<double>(b.bins);
    bands.push_back(b);
    lo = hi;
  }
  std::vector<double> around;
  for (std::size_t i = 0; i < bands.size(); ++i) {
    around.clear();
    for (std::size_t j = i >= kHalfOctave ? i - kHalfOctave : 0;
         j < std::min(bands.size(), i + kHalfOctave + 1); ++j)
      if (j != i && bands[j].bins >= kMinBins) around.push_back(bands[j].mean);
    if (bands[i].bins < kMinBins || around.size() < kHalfOctave) continue;
    std::nth_element(around.begin(),
                     around.begin() + static_cast<std::ptrdiff_t>(around.size() / 2), around.end());
    const double background = around[around.size() / 2];
    bands[i].z = (bands[i].mean / background - 1.0) *
                 std::sqrt(static_cast<double>(bands[i].bins) / kHannInflation);
  }
  std::vector<const Band*> maxima;
  for (std::size_t i = 0; i < bands.size(); ++i)
    if (bands[i].z >= kBroadPeakZ && (i == 0 || bands[i].z >= bands[i - 1].z) &&
        (i + 1 == bands.size() || bands[i].z >= bands[i + 1].z))
      maxima.push_back(&bands[i]);
  std::sort(maxima.begin(), maxima.end(), [](const Band* a, const Band* b) { return a->z > b->z; });
  std::vector<std::pair<double, double>> out;
  for (const Band* b : maxima) {
    if (out.size() == count) break;
    if (std::none_of(out.begin(), out.end(),
                     [&](const auto& o) { return std::abs(std::log2(b->f / o.first)) < 0.5; }))
      out.emplace_back(b->f, b->z);
  }
  return out;
}

// The frequency's track: in each piece of L seconds, L the longest of T / 128 (enough pieces for
// their correlation), 32 coherence times q / (pi f0) (a piece resolves the peak) and 8 / spread
// (its bins resolve the wander), the centroid of the Hann periodogram's excess over its lower
// quartile within f0 +- 3 spread (the quartile of the bins within +- 6 spread, of which the peak
// holds about a third). A Gauss-Markov wander of correlation time tau makes consecutive pieces'
// centroids correlate by about exp(-L / tau), so tau = -L / ln rho of their lag-1 correlation rho.
// The centroids' own noise lowers rho, and a wander with memory longer than one time constant
// (the ADIS16405 z gyroscopes': 144-574 s from 60 s pieces, 151-1082 s from 120 s ones) raises
// tau with L: the estimate errs short, towards replicas that vary less than the record, the strict
// side. Fewer than 8 pieces, or rho <= 0, give L / 2; at most the record's length.
double wander_time(std::span<const double> record, double rate_hz, double f0, double spread,
                   double q) {
  const double t_record = static_cast<double>(record.size()) / rate_hz;
  const double l_s = std::max({t_record / 128.0, 32.0 * q / (std::numbers::pi * f0), 8.0 / spread});
  const auto len = 2 * static_cast<std::int64_t>(0.5 * l_s * rate_hz);
  const std::int64_t pieces = len >= 16 ? static_cast<std::int64_t>(record.size()) / len : 0;
  if (pieces < 8) return std::min(0.5 * l_s, t_record);
  const PsdPlan plan(len);
  std::vector<double> track, near;
  for (std::int64_t i = 0; i < pieces; ++i) {
    const PsdResult p =
        plan.welch(record.subspan(static_cast<std::size_t>(i * len), static_cast<std::size_t>(len)),
                   rate_hz, 1);
    near.clear();
    for (std::size_t k = 1; k < p.size(); ++k)
      if (std::abs(static_cast<double>(k) * p.df_hz - f0) <= 6.0 * spread) near.push_back(p.psd[k]);
    if (near.size() < 8) return std::min(0.5 * l_s, t_record);
    const double bg = lower_quartile(near);
    double sum = 0.0, moment = 0.0;
    for (std::size_t k = 1; k < p.size(); ++k)
      if (const double f = static_cast<double>(k) * p.df_hz; std::abs(f - f0) <= 3.0 * spread) {
        sum += std::max(p.psd[k] - bg, 0.0);
        moment += f * std::max(p.psd[k] - bg, 0.0);
      }
    track.push_back(sum > 0.0 ? moment / sum : f0);
  }
  double mean = 0.0;
  for (const double v : track)
    mean += v / static_cast<double>(track.size());
  double c0 = 0.0, c1 = 0.0;
  for (std::size_t i = 0; i < track.size(); ++i) {
    c0 += (track[i] - mean) * (track[i] - mean);
    if (i > 0) c1 += (track[i] - mean) * (track[i - 1] - mean);
  }
  const double rho = c0 > 0.0 ? c1 / c0 : 0.0;
  if (!(rho > 0.0)) return 0.5 * l_s;
  return std::min(-l_s / std::log(std::min(rho, 0.999999)), t_record);
}

}  // namespace allanlot::kernels::diagnose_detail
