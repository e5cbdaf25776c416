#include "kernels/uncertainty/chi2.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Enough for a = 1e12: both expansions need O(sqrt(a)) terms near x = a.
constexpr int kMaxTerms = 10'000'000;

// ln Gamma(x) for x > 0. std::lgamma writes the global `signgam` in glibc, a data race when
// several threads evaluate confidence intervals, so the function is computed here: the
// recurrence Gamma(x) = Gamma(x + 1) / x lifts x to >= 15, where Stirling's series with terms up
// to x^-11 (Abramowitz & Stegun 6.1.40) has a truncation error below 1e-16.
double log_gamma(double x) {
  double shift = 0.0;
  double prod = 1.0;
  while (x < 15.0) {
    prod *= x;
    x += 1.0;
    if (prod > 1e280) {  // keep the product finite; its log is accumulated separately
      shift += std::log(prod);
      prod = 1.0;
    }
  }
  shift += std::log(prod);
  const double inv = 1.0 / x;
  const double inv2 = inv * inv;
  // Bernoulli-number coefficients B_{2k} / (2k (2k - 1)) for k = 1..6.
  const double series =
      inv *
      (1.0 / 12.0 + inv2 * (-1.0 / 360.0 +
                            inv2 * (1.0 / 1260.0 +
                                    inv2 * (-1.0 / 1680.0 +
                                            inv2 * (1.0 / 1188.0 + inv2 * (-691.0 / 360360.0))))));
  constexpr double half_log_2pi = 0.91893853320467274178;
  return (x - 0.5) * std::log(x) - x + half_log_2pi + series - shift;
}

void check_args(double a, double x) {
  if (!(a > 0.0) || !std::isfinite(a))
    throw std::invalid_argument("incomplete gamma: a must be finite and > 0, got " +
                                std::to_string(a));
  if (!(x >= 0.0)) throw std::invalid_argument("incomplete gamma: x must be >= 0");
}

// x^a e^-x / Gamma(a), the common prefactor of both expansions, in logs to avoid overflow.
double prefactor(double a, double x) {
  return std::exp(a * std::log(x) - x - log_gamma(a));
}

// P(a, x) by the series sum_n x^n / (a (a+1) ... (a+n)) (A&S 6.5.29); for x < a + 1.
double p_series(double a, double x) {
  double term = 1.0 / a;
  double sum = term;
  for (int n = 1; n < kMaxTerms; ++n) {
    term *= x / (a + n);
    sum += term;
    if (term < sum * kEps) break;
  }
  return sum * prefactor(a, x);
}

// Q(a, x) by Legendre's continued fraction (A&S 6.5.31) in modified Lentz form; for x >= a + 1.
double q_continued_fraction(double a, double x) {
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < kMaxTerms; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < kEps) break;
  }
  return h * prefactor(a, x);
}

// I_x(a, b) by the continued fraction 1 / (1 + d_1 / (1 + d_2 / (1 + ...))) of DLMF 8.17.22,
// d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)),
// d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m)), times x^a (1 - x)^b / (a B(a, b)).
double beta_continued_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m < kMaxTerms; ++m) {
    for (int odd = 0; odd < 2; ++odd) {
      const double dm = odd == 0
                            ? m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m))
                            : -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
      d = 1.0 + dm * d;
      if (std::fabs(d) < tiny) d = tiny;
      c = 1.0 + dm / c;
      if (std::fabs(c) < tiny) c = tiny;
      d = 1.0 / d;
      h *= d * c;
      if (odd == 1 && std::fabs(d * c - 1.0) < kEps) {
        const double log_front = a * std::log(x) + b * std::log1p(-x) - std::log(a) -
                                 (log_gamma(a) + log_gamma(b) - log_gamma(a + b));
        return std::exp(log_front) * h;
      }
    }
  }
  throw std::runtime_error("beta_inc: continued fraction did not converge");
}

double chi2_pdf(double x, double dof) {
  const double k = 0.5 * dof;
  return 0.5 * std::exp((k - 1.0) * std::log(0.5 * x) - 0.5 * x - log_gamma(k));
}

}  // namespace

double gamma_p(double a, double x) {
  check_args(a, x);
  if (x == 0.0) return 0.0;
  if (std::isinf(x)) return 1.0;
  return x < a + 1.0 ? p_series(a, x) : 1.0 - q_continued_fraction(a, x);
}

double gamma_q(double a, double x) {
  check_args(a, x);
  if (x == 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  return x < a + 1.0 ? 1.0 - p_series(a, x) : q_continued_fraction(a, x);
}

double beta_inc(double a, double b, double x) {
  if (!(a > 0.0) || !(b > 0.0) || !std::isfinite(a) || !std::isfinite(b) || !(x >= 0.0) ||
      !(x <= 1.0))
    throw std::invalid_argument("beta_inc: need a, b > 0 and 0 <= x <= 1");
  if (x == 0.0) return 0.0;
  if (x == 1.0) return 1.0;
  if (x < (a + 1.0) / (a + b + 2.0)) return beta_continued_fraction(a, b, x);
  return 1.0 - beta_continued_fraction(b, a, 1.0 - x);
}

double student_t_two_sided(double t, double nu) {
  if (!(nu > 0.0)) throw std::invalid_argument("student_t_two_sided: nu must be > 0");
  if (std::isnan(t)) throw std::invalid_argument("student_t_two_sided: t is NaN");
  if (std::isinf(t)) return 0.0;
  return beta_inc(0.5 * nu, 0.5, nu / (nu + t * t));
}

double chi2_cdf(double x, double dof) {
  if (!(dof > 0.0)) throw std::invalid_argument("chi2_cdf: dof must be > 0");
  return gamma_p(0.5 * dof, 0.5 * x);
}

double chi2_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument("chi2_quantile: p must be in (0, 1), got " + std::to_string(p));
  if (!(dof > 0.0) || !std::isfinite(dof))
    throw std::invalid_argument("chi2_quantile: dof must be finite and > 0, got " +
                                std::to_string(dof));
  const double a = 0.5 * dof;
  // Solve in whichever tail is smaller so that the residual keeps its relative accuracy:
  // F(x) - p for p <= 1/2, (1 - p) - Q(x) for p > 1/2; both increase with x.
  const bool upper = p > 0.5;
  const double target = upper ? 1.0 - p : p;
  const auto residual = [&](double x) {
    return upper ? target - gamma_q(a, 0.5 * x) : gamma_p(a, 0.5 * x) - target;
  };

  // Bracket [lo, hi] with residual(lo) <= 0 <= residual(hi), starting from the mean.
  double lo = dof, hi = dof;
  if (residual(dof) < 0.0) {
    do {
      lo = hi;
      hi *= 2.0;
    } while (residual(hi) < 0.0 && std::isfinite(hi));
  } else {
    int halvings = 0;
    do {
      hi = lo;
      lo *= 0.5;
    } while (residual(lo) > 0.0 && ++halvings < 2000 && lo > 0.0);
  }

  // Newton's method on t = ln x for g(t) = ln(tail(x)) - ln(target): the tail probability
  // behaves like a power of x near 0 and like exp(-x/2) far out, so g is nearly linear in t
  // and the iteration converges in a few steps even for dof << 1, where Newton on x itself
  // overshoots. A step that leaves the bracket is replaced by a geometric bisection.
  const auto tail = [&](double x) { return upper ? gamma_q(a, 0.5 * x) : gamma_p(a, 0.5 * x); };
  const double log_target = std::log(target);
  // Geometric means as products of square roots: lo * hi underflows for tiny quantiles.
  const auto mid = [&] { return lo > 0.0 ? std::sqrt(lo) * std::sqrt(hi) : 0.5 * hi; };
  double x = mid();
  for (int it = 0; it < 300; ++it) {
    // One incomplete gamma a step, for both the residual and the slope: for a large dof it
    // is the whole cost of the quantile (O(sqrt(a)) terms of the series or continued fraction).
    const double t = tail(x);
    const double f = upper ? target - t : t - target;  // residual(x)
    if (f == 0.0) return x;
    if (f < 0.0)
      lo = x;
    else
      hi = x;
    const double slope = (upper ? -1.0 : 1.0) * x * chi2_pdf(x, dof) / t;  // d ln(tail) / d ln x
    double next = std::numeric_limits<double>::quiet_NaN();
    if (t > 0.0 && slope != 0.0 && std::isfinite(slope))
      next = x * std::exp(-(std::log(t) - log_target) / slope);
    if (std::fabs(next - x) <= 4.0 * kEps * x || hi - lo <= 4.0 * kEps * hi) return x;
    if (!(next > lo && next < hi)) next = mid();  // outside the bracket (or NaN): bisect
    x = next;
  }
  return x;
}

// psi(x) and psi'(x) for x > 0 (chi2.hpp): the recurrences psi(x) = psi(x+1) - 1/x and
// psi'(x) = psi'(x+1) + 1/x^2 up to x >= 6, then the asymptotic series (Abramowitz & Stegun
// 6.3.18 and 6.4.12), whose truncation error there is below 1e-12.
double digamma(double x) {
  double r = 0.0;
  while (x < 6.0) {
    r -= 1.0 / x;
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + std::log(x) - 0.5 / x -
         f * (1.0 / 12 - f * (1.0 / 120 - f * (1.0 / 252 - f * (1.0 / 240 - f / 132))));
}

double trigamma(double x) {
  double r = 0.0;
  while (x < 6.0) {
    r += 1.0 / (x * x);
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + 1.0 / x + 0.5 * f + f / x * (1.0 / 6 - f * (1.0 / 30 - f * (1.0 / 42 - f / 30)));
}

}  // namespace allanlot::kernels
