// The sensor's low-pass filter: see lowpass.hpp.
#include "kernels/simulate/lowpass.hpp"

#include "kernels/uncertainty/edf.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace allanlot::kernels {

namespace {

// Cumulative sums H_c(j) = sum_{i <= j} h_i of a filter whose taps sum to 1.
std::vector<double> cumulative(const std::vector<double>& h) {
  std::vector<double> c(h.size());
  double s = 0.0;
  for (std::size_t j = 0; j < h.size(); ++j)
    c[j] = s += h[j];
  return c;
}

}  // namespace

std::vector<double> lowpass_impulse(const Lowpass& lp, double rate_hz) {
  if (lp.taps > 0) {
    const double whole = std::floor(lp.taps), frac = lp.taps - whole;
    std::vector<double> h(static_cast<std::size_t>(whole), 1.0 / lp.taps);
    if (frac > 0.0) h.push_back(frac / lp.taps);
    return h;
  }
  if (!(lp.cutoff_hz > 0)) return {1.0};
  const double a = -std::expm1(-2.0 * std::numbers::pi * lp.cutoff_hz / rate_hz);
  // The tail beyond J taps holds (1 - a)^J of the total: below 1e-16 from J = ln 1e-16 / ln(1-a).
  const auto taps = static_cast<std::size_t>(std::ceil(std::log(1e-16) / std::log1p(-a))) + 1;
  std::vector<double> h(taps);
  double g = a, sum = 0.0;
  for (double& v : h) {
    v = g;
    sum += g;
    g *= 1.0 - a;
  }
  for (double& v : h)
    v /= sum;  // DC gain exactly 1 for the truncated response
  return h;
}

void apply_lowpass(const Lowpass& lp, double rate_hz, std::span<double> y) {
  if (y.empty() || !lp.active()) return;
  if (lp.cutoff_hz > 0) {
    const double a = -std::expm1(-2.0 * std::numbers::pi * lp.cutoff_hz / rate_hz);
    double s = y[0];
    for (double& v : y) {
      s += a * (v - s);
      v = s;
    }
    return;
  }
  // Moving average over the last `taps` inputs (the fraction on the oldest), those before the
  // record equal to the first sample. A running sum of the whole taps, summed afresh every 1024
  // samples so that rounding cannot accumulate.
  const auto whole = static_cast<std::ptrdiff_t>(std::floor(lp.taps));
  const double frac = lp.taps - static_cast<double>(whole);
  const std::vector<double> x(y.begin(), y.end());
  const auto in = [&](std::ptrdiff_t k) {
    return x[static_cast<std::size_t>(std::max<std::ptrdiff_t>(k, 0))];
  };
  double sum = 0.0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    const auto kk = static_cast<std::ptrdiff_t>(k);
    if (k % 1024 == 0) {
      sum = 0.0;
      for (std::ptrdiff_t j = 0; j < whole; ++j)
        sum += in(kk - j);
    } else {
      sum += in(kk)-in(kk - whole);
    }
    y[k] = (sum + frac * in(kk - whole)) / lp.taps;
  }
}

double lowpass_gain2(const Lowpass& lp, double rate_hz, double f_hz) {
  const double w = 2.0 * std::numbers::pi * f_hz / rate_hz;
  if (lp.taps > 0) {
    double re = 0.0, im = 0.0;
    const std::vector<double> h = lowpass_impulse(lp, rate_hz);
    for (std::size_t j = 0; j < h.size(); ++j) {
      re += h[j] * std::cos(w * static_cast<double>(j));
      im -= h[j] * std::sin(w * static_cast<double>(j));
    }
    return re * re + im * im;
  }
  if (!(lp.cutoff_hz > 0)) return 1.0;
  const double a = -std::expm1(-2.0 * std::numbers::pi * lp.cutoff_hz / rate_hz);
  const double b = 1.0 - a;
  return a * a / (1.0 - 2.0 * b * std::cos(w) + b * b);
}

double lowpass_white_fm_factor(const Lowpass& lp, double rate_hz, std::int64_t m) {
  if (m < 1) throw std::invalid_argument("lowpass_white_fm_factor: m must be >= 1");
  if (!lp.active()) return 1.0;
  const std::vector<double> hc = cumulative(lowpass_impulse(lp, rate_hz));
  const auto j_len = static_cast<std::int64_t>(hc.size());
  const auto at = [&](std::int64_t k) {
    return k < 0 ? 0.0 : k >= j_len ? 1.0 : hc[static_cast<std::size_t>(k)];
  };
  double s = 0.0;
  if (m >= j_len) {
    // The three edges of the window pair do not overlap: between them m g_k = +-1.
    s = 2.0 * static_cast<double>(m - j_len);
    for (std::int64_t j = 0; j < j_len; ++j) {
      const double c = at(j);
      s += c * c + (2.0 * c - 1.0) * (2.0 * c - 1.0) + (1.0 - c) * (1.0 - c);
    }
  } else {
    for (std::int64_t k = 0; k < 2 * m + j_len; ++k) {
      const double g = 2.0 * at(k - m) - at(k) - at(k - 2 * m);
      s += g * g;
    }
  }
  return s / (2.0 * static_cast<double>(m));
}

double lowpass_white_pm_factor(const Lowpass& lp, double rate_hz, std::int64_t m) {
  if (m < 1) throw std::invalid_argument("lowpass_white_pm_factor: m must be >= 1");
  if (!lp.active()) return 1.0;
  const std::vector<double> h = lowpass_impulse(lp, rate_hz);
  const auto j_len = static_cast<std::int64_t>(h.size());
  const auto at = [&](std::int64_t k) {
    return k < 0 || k >= j_len ? 0.0 : h[static_cast<std::size_t>(k)];
  };
  double s = 0.0;
  if (m >= j_len) {
    for (const double v : h)
      s += 6.0 * v * v;
  } else {
    for (std::int64_t k = 0; k < 2 * m + j_len; ++k) {
      const double g = at(k) - 2.0 * at(k - m) + at(k - 2 * m);
      s += g * g;
    }
  }
  return s / 6.0;
}

std::vector<double> lowpass_autocorrelation(const Lowpass& lp, double rate_hz) {
  const std::vector<double> h = lowpass_impulse(lp, rate_hz);
  std::vector<double> rho(h.size(), 0.0);
  for (std::size_t j = 0; j < h.size(); ++j)
    for (std::size_t i = 0; i + j < h.size(); ++i)
      rho[j] += h[i] * h[i + j];
  return rho;
}

namespace {

// v(a) = 2 (a - 1 + e^-a) = 2 sum_{k >= 2} (-a)^k / k!: the series below a = 0.5, where the
// closed form loses the leading a^2 to cancellation (terms fall by a / k, 1e-16 by k = 25).
double ou_sum_var(double a) {
  if (a >= 0.5) return 2.0 * (a + std::expm1(-a));
  double sum = 0.0, term = a * a / 2.0;
  for (int k = 2; k <= 25; ++k) {
    sum += (k % 2 == 0 ? term : -term);
    term *= a / (k + 1);
  }
  return 2.0 * sum;
}

}  // namespace

double lowpass_structure_sum(const std::function<double(double)>& d, double o,
                             const std::vector<double>& rho) {
  double s = rho[0] * d(std::abs(o));
  for (std::size_t j = 1; j < rho.size(); ++j) {
    const auto jd = static_cast<double>(j);
    s += rho[j] * (d(std::abs(o - jd)) + d(std::abs(o + jd)));
  }
  return s;
}

double lowpass_structure_avar(const std::function<double(double)>& d, double m,
                              const std::vector<double>& rho) {
  const auto f = [&](double o) { return lowpass_structure_sum(d, o, rho); };
  return (8.0 * f(m) - 2.0 * f(2.0 * m) - 6.0 * f(0.0)) / (4.0 * m * m);
}

double lowpass_markov_avar(double sigma, double tau_c_s, double rate_hz, std::int64_t m,
                           const std::vector<double>& rho) {
  if (m < 1) throw std::invalid_argument("lowpass_markov_avar: m must be >= 1");
  const double h = 1.0 / rate_hz;
  const double scale = sigma * sigma * tau_c_s * tau_c_s / (h * h);
  return scale * lowpass_structure_avar([&](double k) { return ou_sum_var(k * h / tau_c_s); },
                                        static_cast<double>(m), rho);
}

std::int64_t lowpass_first_m(const Lowpass& lp, double rate_hz, std::int64_t n_samples) {
  if (!lp.active()) return 1;
  const std::int64_t j_len = static_cast<std::int64_t>(lowpass_impulse(lp, rate_hz).size());
  const FiniteDifferenceKind oavar{2, true, false};
  const auto ok = [&](std::int64_t m) {
    if (greenhall_terms(oavar, m, n_samples + 1) < 1) return true;
    const double sd = std::sqrt(2.0 / edf_greenhall(0, oavar, m, n_samples + 1));
    return m >= j_len && std::abs(1.0 - lowpass_white_fm_factor(lp, rate_hz, m)) < 0.5 * sd;
  };
  // The bias falls as 1/m and the standard deviation grows as sqrt(m): once below, it stays.
  std::int64_t hi = 1;
  while (!ok(hi))
    hi *= 2;
  std::int64_t lo = hi / 2;  // not ok (or 0)
  while (hi - lo > 1) {
    const std::int64_t mid = lo + (hi - lo) / 2;
    (ok(mid) ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace allanlot::kernels
