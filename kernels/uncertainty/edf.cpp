#include "kernels/uncertainty/edf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

using Real = long double;  // the filtered covariances are differences of large terms
constexpr Real kInf = std::numeric_limits<Real>::infinity();
constexpr int kJmax = 100;  // Greenhall & Riley 2003, sec. 3.4: "J_max = 100 is suggested"

// Natural logarithm of t > 0 in long double from +, -, *, / alone. std::log of a long double is
// the x87 instruction fyl2x on x86-64, whose last bits differ between CPU models, so every edf
// (and every interval) would differ between machines by an ulp now and then; this gives the
// same bits everywhere. t = f 2^e with f in [sqrt(1/2), sqrt(2)) (frexp is exact), and
// ln f = 2 atanh(z), z = (f - 1) / (f + 1), |z| <= 0.172: the odd series to z^41 (15 terms,
// the first left out below 1e-31) in Horner form, then e ln 2.
Real log_real(Real t) {
  constexpr Real kLn2 = 0.693147180559945309417232121458176568L;
  constexpr Real kSqrtHalf = 0.707106781186547524400844362104849039L;
  int e = 0;
  Real f = std::frexp(t, &e);
  if (f < kSqrtHalf) {
    f *= 2;
    --e;
  }
  const Real z = (f - 1) / (f + 1);
  const Real z2 = z * z;
  Real series = Real(1) / 41;
  for (int k = 39; k >= 1; k -= 2)
    series = Real(1) / k + z2 * series;
  return 2 * z * series + static_cast<Real>(e) * kLn2;
}

// Generalized autocovariance of the continuous-time power-law process w(t) whose derivative
// has spectrum f^alpha (Greenhall & Riley 2003, eq. (7)), up to a constant factor per alpha
// that cancels in the edf (only ratios of covariances of one alpha enter).
Real sw(Real t, int alpha) {
  t = std::fabs(t);
  switch (alpha) {
  case 2:
    return -t;
  case 1:
    return t == 0 ? Real(0) : t * t * log_real(t);
  case 0:
    return t * t * t;
  case -1:
    return t == 0 ? Real(0) : -t * t * t * t * log_real(t);
  case -2:
    return -t * t * t * t * t;
  case -3:
    return t == 0 ? Real(0) : t * t * t * t * t * t * log_real(t);
  case -4:
    return t * t * t * t * t * t * t;
  default:
    break;
  }
  throw std::invalid_argument("edf: alpha must be in -4..2, got " + std::to_string(alpha));
}

// Covariance of the filtered phase (eq. (8)): F = m for unmodified variances, F = 1 for
// modified ones; F = infinity is the limit used for long unmodified filters when alpha <= 0.
Real sx(Real t, Real F, int alpha) {
  if (std::isinf(F)) return sw(t, alpha + 2);
  return F * F * (2 * sw(t, alpha) - sw(t - 1 / F, alpha) - sw(t + 1 / F, alpha));
}

// Covariance of the d-th difference of the filtered phase (eq. (9)), binomial weights of the
// (2d)-th central difference.
Real sz(Real t, Real F, int alpha, int d) {
  switch (d) {
  case 1:
    return 2 * sx(t, F, alpha) - sx(t - 1, F, alpha) - sx(t + 1, F, alpha);
  case 2:
    return 6 * sx(t, F, alpha) - 4 * (sx(t - 1, F, alpha) + sx(t + 1, F, alpha)) +
           (sx(t - 2, F, alpha) + sx(t + 2, F, alpha));
  case 3:
    return 20 * sx(t, F, alpha) - 15 * (sx(t - 1, F, alpha) + sx(t + 1, F, alpha)) +
           6 * (sx(t - 2, F, alpha) + sx(t + 2, F, alpha)) -
           (sx(t - 3, F, alpha) + sx(t + 3, F, alpha));
  default:
    break;
  }
  throw std::invalid_argument("edf: d must be 1, 2 or 3, got " + std::to_string(d));
}

// Eq. (10): s_z(0)^2 + (1 - J/M) s_z(J/S)^2 + 2 sum_{j=1}^{J-1} (1 - j/M) s_z(j/S)^2.
Real basic_sum(Real J, Real M, Real S, Real F, int alpha, int d) {
  const Real s0 = sz(0, F, alpha, d);
  const Real sJ = sz(J / S, F, alpha, d);
  Real sum = 0;
  for (int j = 1; j < static_cast<int>(J); ++j) {
    const Real s = sz(j / S, F, alpha, d);
    sum += (1 - j / M) * s * s;
  }
  return s0 * s0 + (1 - J / M) * sJ * sJ + 2 * sum;
}

// 1/edf from the basic sum: BasicSum / (M s_z(0)^2) (sec. 3.5).
Real inv_edf_sum(Real J, Real M, Real S, Real F, int alpha, int d) {
  const Real s0 = sz(0, F, alpha, d);
  return basic_sum(J, M, S, F, alpha, d) / (M * s0 * s0);
}

struct Coeff {
  double a0, a1;
};

// Table 1 (modified variances, F = 1): 1/edf ~ (a0 - a1/r) / r for large r. Rows alpha = 2..-4,
// columns d = 1..3; {0, 0} where alpha + 2d <= 1.
constexpr Coeff kTable1[7][3] = {
    {{2.0 / 3, 1.0 / 3}, {7.0 / 9, 1.0 / 2}, {22.0 / 25, 2.0 / 3}},
    {{0.840, 0.345}, {0.997, 0.616}, {1.141, 0.843}},
    {{1.079, 0.368}, {1.033, 0.607}, {1.184, 0.848}},
    {{0, 0}, {1.048, 0.534}, {1.180, 0.816}},
    {{0, 0}, {1.302, 0.535}, {1.175, 0.777}},
    {{0, 0}, {0, 0}, {1.194, 0.703}},
    {{0, 0}, {0, 0}, {1.489, 0.702}},
};
// Table 2 (unmodified variances, F = m), same layout.
constexpr Coeff kTable2[7][3] = {
    {{3.0 / 2, 1.0 / 2}, {35.0 / 18, 1.0}, {231.0 / 100, 3.0 / 2}},
    {{78.6, 25.2}, {790.0, 410.0}, {9950.0, 6520.0}},
    {{2.0 / 3, 1.0 / 6}, {2.0 / 3, 1.0 / 3}, {7.0 / 9, 1.0 / 2}},
    {{0, 0}, {0.852, 0.375}, {0.997, 0.617}},
    {{0, 0}, {1.079, 0.368}, {1.033, 0.607}},
    {{0, 0}, {0, 0}, {1.053, 0.553}},
    {{0, 0}, {0, 0}, {1.302, 0.535}},
};
// Table 3 (unmodified variances, flicker PM): the log(m) denominator b0 + b1 ln m, d = 1..3.
constexpr Coeff kTable3[3] = {{6.0, 4.0}, {15.23, 12.0}, {47.8, 40.0}};

double binomial(int n, int k) {
  double b = 1.0;
  for (int i = 1; i <= k; ++i)
    b = b * (n - k + i) / i;
  return b;
}

void check_kind(int alpha, FiniteDifferenceKind kind, std::int64_t m) {
  if (m < 1) throw std::invalid_argument("edf: m must be >= 1, got " + std::to_string(m));
  if (kind.d < 1 || kind.d > 3)
    throw std::invalid_argument("edf: d must be 1, 2 or 3, got " + std::to_string(kind.d));
  if (alpha < -4 || alpha > 2 || alpha + 2 * kind.d <= 1)
    throw std::invalid_argument(
        "edf: alpha = " + std::to_string(alpha) +
        " is outside -4..2 or does not converge for d = " + std::to_string(kind.d));
}

}  // namespace

std::int64_t greenhall_terms(FiniteDifferenceKind kind, std::int64_t m, std::int64_t n_phase) {
  // L = m/F + m d: F = 1 gives m + m d, F = m gives 1 + m d; S = m or 1.
  const std::int64_t L = (kind.modified ? m : 1) + m * kind.d;
  if (n_phase < L) return 0;
  return kind.overlapping ? 1 + (n_phase - L) : 1 + (n_phase - L) / m;
}

std::int64_t greenhall_phase_points(FiniteDifferenceKind kind, std::int64_t m, std::int64_t terms) {
  const std::int64_t L = (kind.modified ? m : 1) + m * kind.d;
  if (terms < 1) return 0;
  return kind.overlapping ? L + terms - 1 : L + (terms - 1) * m;
}

double edf_greenhall(int alpha, FiniteDifferenceKind kind, std::int64_t m, std::int64_t n_phase) {
  check_kind(alpha, kind, m);
  const std::int64_t M_int = greenhall_terms(kind, m, n_phase);
  if (M_int < 1)
    throw std::invalid_argument("edf: no term for m = " + std::to_string(m) +
                                " and N = " + std::to_string(n_phase));
  const int d = kind.d;
  const Real M = static_cast<Real>(M_int);
  const Real mm = static_cast<Real>(m);
  const Real S = kind.overlapping ? mm : 1;
  const Real J = std::min<Real>(M, (d + 1) * S);
  const Real r = M / S;
  const int row = 2 - alpha;
  Real inv = 0;

  if (kind.modified || m == 1) {
    // Case 1 (sec. 3.6.1): modified variances, all alpha; also unmodified ones at m = F = 1.
    if (J <= kJmax) {
      inv = inv_edf_sum(J, M, S, 1, alpha, d);
    } else if (r >= d + 1) {
      const Coeff c = kTable1[row][d - 1];
      inv = (c.a0 - c.a1 / r) / r;
    } else {
      const Real m_prime = kJmax / r;
      inv = inv_edf_sum(kJmax, kJmax, m_prime, 1, alpha, d);
    }
  } else if (alpha <= 0) {
    // Case 2 (sec. 3.6.2): unmodified variances, white FM and below. For long filters the
    // covariance is evaluated in the limit F -> infinity, which avoids the cancellation of the
    // F^2-scaled second difference in eq. (8).
    if (J <= kJmax) {
      const Real F = mm * (d + 1) <= kJmax ? mm : kInf;
      inv = inv_edf_sum(J, M, S, F, alpha, d);
    } else if (r >= d + 1) {
      const Coeff c = kTable2[row][d - 1];
      inv = (c.a0 - c.a1 / r) / r;
    } else {
      const Real m_prime = kJmax / r;
      inv = inv_edf_sum(kJmax, kJmax, m_prime, kInf, alpha, d);
    }
  } else if (alpha == 1) {
    // Case 3 (sec. 3.6.3): unmodified variances, flicker PM, whose variance grows as ln m.
    const Coeff b = kTable3[d - 1];
    const Real log_den = b.a0 + b.a1 * log_real(mm);
    if (J <= kJmax) {
      inv = inv_edf_sum(J, M, S, mm, 1, d);
    } else if (r >= d + 1) {
      const Coeff c = kTable2[row][d - 1];
      inv = (c.a0 - c.a1 / r) / (r * log_den * log_den);
    } else {
      const Real m_prime = kJmax / r;
      inv = basic_sum(kJmax, kJmax, m_prime, m_prime, 1, d) / (kJmax * log_den * log_den);
    }
  } else {
    // Case 4 (sec. 3.6.4): unmodified variances, white PM: the differences are correlated only
    // over K = ceil(r) lags, which gives a closed form.
    const std::int64_t K = static_cast<std::int64_t>(std::ceil(static_cast<double>(r)));
    if (K <= d) {
      const double c2d = binomial(2 * d, d);
      Real s = 0;
      for (std::int64_t k = 1; k < K; ++k) {
        const double b = binomial(2 * d, d - static_cast<int>(k));
        s += (1 - static_cast<Real>(k) / r) * b * b;
      }
      inv = (1 + 2 * s / (c2d * c2d)) / M;
    } else {
      const Coeff c = kTable2[row][d - 1];
      inv = (c.a0 - c.a1 / r) / M;
    }
  }
  return static_cast<double>(1 / inv);
}

double edf_totvar(int alpha, std::int64_t m, std::int64_t n_phase) {
  if (m < 1) throw std::invalid_argument("edf_totvar: m must be >= 1, got " + std::to_string(m));
  if (n_phase < 2)
    throw std::invalid_argument("edf_totvar: need >= 2 phase points, got " +
                                std::to_string(n_phase));
  const double T_over_tau = static_cast<double>(n_phase - 1) / static_cast<double>(m);
  switch (alpha) {
  case 0:
    return 1.50 * T_over_tau;
  case -1:
    return 1.17 * T_over_tau - 0.22;
  case -2:
    return 0.93 * T_over_tau - 0.36;
  case 2: {
    // Howe's fits stop at white FM. For PM noise Stable32 1.60 takes the simple edf of the
    // overlapping Allan variance (SP1065 sec. 5.3.3, Table 5, p. 38; Howe, Allan & Barnes
    // 1981): its TOTDEV bounds on a GPS receiver's and a time-interval counter's phase imply
    // that edf within 1-2.5 % at every m, where 1.5 T/tau was 3 times too large at m = 1 and
    // 100 times too small at m = 2048 (docs/statistics.md). White PM: (N+1)(N-2m) / 2(N-m).
    const auto N = static_cast<double>(n_phase), M = static_cast<double>(m);
    return std::max(1.0, (N + 1.0) * (N - 2.0 * M) / (2.0 * (N - M)));
  }
  case 1: {
    // Flicker PM: exp(sqrt(ln((N-1)/2m) ln((2m+1)(N-1)/4))), the same table.
    const auto N = static_cast<double>(n_phase), M = static_cast<double>(m);
    const double a = std::log((N - 1.0) / (2.0 * M));
    const double b = std::log((2.0 * M + 1.0) * (N - 1.0) / 4.0);
    return a > 0.0 && b > 0.0 ? std::max(1.0, std::exp(std::sqrt(a * b))) : 1.0;
  }
  default:
    break;
  }
  throw std::invalid_argument("edf_totvar: alpha must be in -2..2, got " + std::to_string(alpha));
}

double edf_mtotvar(int alpha, std::int64_t m, std::int64_t n_phase) {
  if (m < 1) throw std::invalid_argument("edf_mtotvar: m must be >= 1, got " + std::to_string(m));
  if (n_phase < 2)
    throw std::invalid_argument("edf_mtotvar: need >= 2 phase points, got " +
                                std::to_string(n_phase));
  if (alpha < -2 || alpha > 2)
    throw std::invalid_argument("edf_mtotvar: alpha must be in -2..2, got " +
                                std::to_string(alpha));
  static constexpr double b[] = {0.75, 0.85, 1.10, 1.20, 1.90};  // alpha = -2 .. 2
  static constexpr double c[] = {0.31, 0.50, 1.20, 1.40, 2.10};
  const double T_over_tau = static_cast<double>(n_phase - 1) / static_cast<double>(m);
  const auto k = static_cast<std::size_t>(alpha + 2);
  return std::max(1.0, b[k] * T_over_tau - c[k]);
}

double htotvar_bias(int alpha) {
  switch (alpha) {
  case 0:
    return 0.995;
  case -1:
    return 0.851;
  case -2:
    return 0.771;
  default:
    return 1.0;
  }
}

}  // namespace allanlot::kernels

namespace allanlot::kernels {
namespace {

void check_edf_args(const char* name, int alpha, int alpha_lo, int alpha_hi, std::int64_t m,
                    std::int64_t m_min, std::int64_t n_phase, std::int64_t n_min) {
  const std::string f(name);
  if (m < m_min)
    throw std::invalid_argument(f + ": m must be >= " + std::to_string(m_min) + ", got " +
                                std::to_string(m));
  if (n_phase < n_min)
    throw std::invalid_argument(f + ": need >= " + std::to_string(n_min) + " phase points, got " +
                                std::to_string(n_phase));
  if (alpha < alpha_lo || alpha > alpha_hi)
    throw std::invalid_argument(f + ": alpha must be in " + std::to_string(alpha_lo) + ".." +
                                std::to_string(alpha_hi) + ", got " + std::to_string(alpha));
}

}  // namespace

double edf_htotvar(int alpha, std::int64_t m, std::int64_t n_phase) {
  check_edf_args("edf_htotvar", alpha, -2, 0, m, 1, n_phase, 2);
  // Howe & Tasset's Table I (b0, b1), alpha = -2, -1, 0.
  static constexpr double b0[] = {0.938, 0.868, 0.559};
  static constexpr double b1[] = {1.696, 1.140, 1.004};
  const double T_over_tau = static_cast<double>(n_phase - 1) / static_cast<double>(m);
  const auto k = static_cast<std::size_t>(alpha + 2);
  return std::max(1.0, T_over_tau / (b0[k] + b1[k] / T_over_tau));
}

double edf_theo1(int alpha, std::int64_t m, std::int64_t n_phase) {
  check_edf_args("edf_theo1", alpha, -2, 2, m, 2, n_phase, m + 1);
  const double r = 0.75 * static_cast<double>(m);  // Thêo1's tau / tau0
  const double n = static_cast<double>(n_phase);
  double edf = 0.0;
  switch (alpha) {
  case 2:
    edf = 0.86 * (n + 1.0) * (n - 4.0 * r / 3.0) / (n - r) * (r / (r + 1.14));
    break;
  case 1:
    edf = (4.798 * n * n - 6.374 * n * r + 12.387 * r) / (std::sqrt(r + 36.6) * (n - r)) *
          (r / (r + 0.3));
    break;
  case 0: {
    const double r15 = r * std::sqrt(r);
    edf = ((4.1 * n + 0.8) / r - (3.1 * n + 6.5) / n) * (r15 / (r15 + 5.2));
    break;
  }
  case -1: {
    const double r3 = r * r * r;
    edf = (2.0 * n * n - 1.3 * n * r - 3.5 * r) / (n * r) * (r3 / (r3 + 2.3));
    break;
  }
  default: {
    const double a = 4.4 * n - 1.0;
    const double b = 4.4 * n - 3.0;
    edf = (4.4 * n - 2.0) / (2.9 * r) * ((a * a - 8.6 * r * a + 11.4 * r * r) / (b * b));
    break;
  }
  }
  return std::max(1.0, edf);
}

double edf_pvar(int alpha, std::int64_t m, std::int64_t n_phase) {
  check_edf_args("edf_pvar", alpha, -2, 2, m, 1, n_phase, 2 * m + 1);
  const std::int64_t terms = n_phase - 2 * m;
  // Vernotte et al. fitted eq. (16) for m up to N / 4, i.e. M >= 2m; past it the edf is the
  // floor of one estimate.
  if (terms < 2 * m) return 1.0;
  const double a = static_cast<double>(alpha);
  const double A = 27.0 + a / 4.0 + 5.0 * a * a / 14.0 - 3.0 * a * a * a / 4.0;
  const double ratio = static_cast<double>(m) / static_cast<double>(terms);
  return std::max(1.0, 35.0 / (A * ratio - 12.0 * ratio * ratio));
}

}  // namespace allanlot::kernels
