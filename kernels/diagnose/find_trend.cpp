// The time-domain witness of a ramp (docs/diagnose.md "Ramp, random walk and hump told
// apart"): the record's least-squares slope against the spread the model under test gives it.
//
// The slope of samples y_k at t_k is b = sum w_k y_k with w_k = (t_k - t_mean) / sum (t -
// t_mean)^2. For T = n / rate much longer than a sample its variance under a stationary-increment
// noise of one-sided PSD S(f) is int_0^inf S(f) |W(f)|^2 df, where W, the Fourier transform of the
// continuous weight 12 (t - T/2) / T^3 on [0, T], has |W(f)|^2 = (36 / T^2) j1(pi f T)^2 with
// j1 the spherical Bessel function sin x / x^2 - cos x / x. With x = pi f T:
//   var b = 36 / (pi T^3) int_0^inf S(x / (pi T)) j1(x)^2 dx.
// Checks (tests/kernels/test_diagnose_trend.cpp): white FM (S = 2 N^2) gives 12 N^2 / T^3, the
// discrete sum's N^2 rate / sum t^2; a random walk (S = K^2 / (2 pi^2 f^2)) gives 6 K^2 / (5 T),
// the slope of Brownian motion; flicker is finite because j1^2 ~ x^2 / 9 at x -> 0. A ramp has
// no density (it is what is tested for) and the sinusoids' lines are left out: a line's slope
// is of order A / (f T^2), negligible unless its period is the record's.
#include "kernels/diagnose/diagnose.hpp"

#include "kernels/simulate/simulate.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

double j1_squared(double x) {
  if (x < 1e-3) return x * x / 9.0;  // j1(x) = x / 3 - x^3 / 30 + ...
  const double j = (std::sin(x) - x * std::cos(x)) / (x * x);
  return j * j;
}

}  // namespace

double trend_slope_variance(const ChannelSpec& model, double duration_s) {
  if (!(duration_s > 0) || !std::isfinite(duration_s))
    throw std::invalid_argument("trend_slope_variance: duration_s must be finite and > 0");
  const double pi = std::numbers::pi, t = duration_s;
  // Up to x = 400 (f = 127 / T) j1^2 is integrated as it is, by the midpoint rule at 40 points
  // per unit of x (its period is 2 pi); beyond, where j1^2 oscillates about 1 / (2 x^2) with an
  // error O(1/x^3), on a log grid of 1000 points per decade up to Nyquist. The model's PSD is
  // evaluated on all the points at once (a wandering resonance's nodes once, not per point).
  const double x_split = 400.0, x_max = pi * 0.5 * model.rate_hz * t;
  const double h = 1.0 / 40.0;
  std::vector<double> x_lin, x_log;
  double dl = 0.0;
  for (double x = 0.5 * h; x < std::min(x_split, x_max); x += h)
    x_lin.push_back(x);
  if (x_max > x_split) {
    const double lx = std::log(x_split), step = std::log(10.0) / 1000.0;
    const int n = static_cast<int>(std::ceil((std::log(x_max) - lx) / step));
    dl = (std::log(x_max) - lx) / n;
    for (int i = 0; i < n; ++i)
      x_log.push_back(std::exp(lx + (i + 0.5) * dl));
  }
  const auto psd_at = [&](const std::vector<double>& xs) {
    std::vector<double> f(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i)
      f[i] = xs[i] / (pi * t);
    return model_psd_one_sided(model, f);
  };
  const std::vector<double> s_lin = psd_at(x_lin), s_log = psd_at(x_log);
  double sum = 0.0;
  for (std::size_t i = 0; i < x_lin.size(); ++i)
    sum += s_lin[i] * j1_squared(x_lin[i]) * h;
  for (std::size_t i = 0; i < x_log.size(); ++i)
    sum += s_log[i] * (0.5 / (x_log[i] * x_log[i])) * x_log[i] * dl;
  return 36.0 / (pi * t * t * t) * sum;
}

double least_squares_slope(std::span<const double> y, double rate_hz) {
  const double n = static_cast<double>(y.size()), t_mean = 0.5 * n;
  double y_mean = 0.0, sty = 0.0, stt = 0.0;
  for (const double v : y)
    y_mean += v;
  y_mean /= n;
  for (std::size_t k = 0; k < y.size(); ++k) {
    const double tk = static_cast<double>(k) + 0.5 - t_mean;
    sty += tk * (y[k] - y_mean);
    stt += tk * tk;
  }
  return sty / stt * rate_hz;
}

TrendWitness find_trend(std::span<const double> rate, double rate_hz, const ChannelSpec& model,
                        double false_alarm) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz))
    throw std::invalid_argument("find_trend: rate_hz must be finite and > 0");
  if (!(false_alarm > 0 && false_alarm < 1))
    throw std::invalid_argument("find_trend: false_alarm must be in (0, 1), got " +
                                std::to_string(false_alarm));
  TrendWitness w;
  w.false_alarm = false_alarm;
  if (rate.size() < 3) return w;
  for (const double v : rate)
    if (!std::isfinite(v)) return w;
  ChannelSpec m = model;
  m.rate_hz = rate_hz;
  const double t = static_cast<double>(rate.size()) / rate_hz;
  w.searched = true;
  w.slope = least_squares_slope(rate, rate_hz);
  w.sigma = std::sqrt(trend_slope_variance(m, t));
  if (!(w.sigma > 0.0)) return w;
  w.z = w.slope / w.sigma;
  w.p_value = std::erfc(std::abs(w.z) / std::numbers::sqrt2);
  w.found = w.p_value < false_alarm;
  return w;
}

}  // namespace allanlot::kernels
