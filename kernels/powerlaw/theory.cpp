#include "kernels/powerlaw/theory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace allanlot::kernels::powerlaw {
namespace {

constexpr double kPi = std::numbers::pi;

void check(int alpha, double tau_s, double tau0_s) {
  if (alpha < -2 || alpha > 2)
    throw std::invalid_argument("power-law alpha must be in -2..2, got " + std::to_string(alpha));
  if (!(tau_s > 0.0) || !(tau0_s > 0.0) || !std::isfinite(tau_s) || !std::isfinite(tau0_s))
    throw std::invalid_argument("power-law theory: tau_s and tau0_s must be finite and > 0");
}

// The number of integers i in [0, m) within [lo, hi].
std::int64_t count_in(std::int64_t lo, std::int64_t hi, std::int64_t m) {
  const std::int64_t a = std::max<std::int64_t>(lo, 0), b = std::min<std::int64_t>(hi, m - 1);
  return b >= a ? b - a + 1 : 0;
}

}  // namespace

double avar_per_h(int alpha, double tau_s, double tau0_s) {
  check(alpha, tau_s, tau0_s);
  const double f_h = 0.5 / tau0_s;
  switch (alpha) {
  case 2:
    return 3.0 * f_h / (4.0 * kPi * kPi * tau_s * tau_s);
  case 1:
    return (1.038 + 3.0 * std::log(2.0 * kPi * f_h * tau_s)) / (4.0 * kPi * kPi * tau_s * tau_s);
  case 0:
    return 1.0 / (2.0 * tau_s);
  case -1:
    return 2.0 * std::numbers::ln2;
  default:
    return 2.0 * kPi * kPi / 3.0 * tau_s;
  }
}

Eq3Squares eq3_squares(double h2, double h0, double hm1, double hm2, double tau0_s) {
  return {h2 * (0.5 / tau0_s) / (4.0 * kPi * kPi), h0 / 2.0, kPi * hm1, 2.0 * kPi * kPi * hm2};
}

double white_fm_mvar(std::int64_t m, double tau0_s) {
  if (m < 1 || !(tau0_s > 0.0)) throw std::invalid_argument("white_fm_mvar: m >= 1, tau0_s > 0");
  // y_j (j in [0, 3m - 1)) is in the later window of term i when i + m <= j <= i + 2m - 1 and in
  // the earlier one when i <= j <= i + m - 1.
  long double sum = 0;
  for (std::int64_t j = 0; j < 3 * m - 1; ++j) {
    const auto c =
        static_cast<long double>(count_in(j - 2 * m + 1, j - m, m) - count_in(j - m + 1, j, m));
    sum += c * c;
  }
  const double tau = static_cast<double>(m) * tau0_s;
  const double md = static_cast<double>(m);
  return static_cast<double>(sum) * tau0_s * tau0_s / (2.0 * tau0_s) / (2.0 * md * md * tau * tau);
}

double mvar_per_h(int alpha, double tau_s, double tau0_s) {
  check(alpha, tau_s, tau0_s);
  switch (alpha) {
  case 2:
    return 3.0 * (0.5 / tau0_s) * tau0_s / (4.0 * kPi * kPi * tau_s * tau_s * tau_s);
  case 1:
    return 3.37 / (4.0 * kPi * kPi * tau_s * tau_s);
  case 0:
    return white_fm_mvar(std::max<std::int64_t>(1, std::llround(tau_s / tau0_s)), tau0_s);
  case -1:
    return 27.0 / 20.0 * std::numbers::ln2;
  default:
    return 11.0 * kPi * kPi / 20.0 * tau_s;
  }
}

}  // namespace allanlot::kernels::powerlaw
