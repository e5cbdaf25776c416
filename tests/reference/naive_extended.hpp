// Naive implementations of the further statistics (MTIE, TIE rms, Theo1, MTOTDEV, TTOTDEV,
// HTOTDEV, PDEV) straight from their published definitions, in long double, with none of the
// kernels' tricks (no deques, no prefix sums, no mean removal): O(N m) or O(N m^2) per m, for
// the short random records of the tests. They take the phase as given (no trend removed), so
// the time-error statistics see the record's own frequency offset, as Stable32 does.
//
// No gaps: the kernels refuse gapped data for these statistics (or, for MTIE and TIE rms,
// skip the windows that touch a gap; see naive_mtie_phase).
#pragma once

#include "reference/naive_allan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace allanlot::test {

/// MTIE, ITU-T G.810 eq. (II.4) / SP1065 sec. 5.2.15: the largest peak-to-peak phase excursion
/// over every window of m + 1 consecutive points x_i .. x_{i+m}; n = N - m windows. Windows
/// with a NaN are skipped (and not counted).
template <class T>
NaiveRow naive_mtie_phase(const std::vector<T>& x, std::int64_t m) {
  const auto N = static_cast<std::int64_t>(x.size());
  long double best = 0;
  std::int64_t n = 0;
  for (std::int64_t i = 0; i + m < N; ++i) {
    long double lo = x[static_cast<std::size_t>(i)], hi = lo;
    bool nan = false;
    for (std::int64_t k = i; k <= i + m; ++k) {
      const long double v = x[static_cast<std::size_t>(k)];
      nan = nan || std::isnan(v);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (nan) continue;
    best = std::max(best, hi - lo);
    ++n;
  }
  return {best, n};
}

/// TIE rms, SP1065 sec. 5.2.16: sqrt of the mean of (x_{i+m} - x_i)^2 over the n = N - m pairs
/// (a pair is skipped when any of x_i .. x_{i+m} is NaN: the kernels' rule, under which a pair
/// whose span touches a gap is left out).
template <class T>
NaiveRow naive_tierms_phase(const std::vector<T>& x, std::int64_t m) {
  const auto N = static_cast<std::int64_t>(x.size());
  const auto nans = nan_prefix(x);
  long double s = 0;
  std::int64_t n = 0;
  for (std::int64_t i = 0; i + m < N; ++i) {
    if (nans[static_cast<std::size_t>(i + m + 1)] != nans[static_cast<std::size_t>(i)]) continue;
    const long double d = static_cast<long double>(x[static_cast<std::size_t>(i + m)]) -
                          static_cast<long double>(x[static_cast<std::size_t>(i)]);
    s += d * d;
    ++n;
  }
  return {n ? std::sqrt(s / n) : 0.0L, n};
}

/// Theo1, SP1065 eq. (30), p. 29 (Howe & Peppas 2000): for even m,
///   Theo1 = 1 / (0.75 (N - m) (m tau0)^2) sum_{i=0}^{N-m-1} sum_{d=0}^{m/2-1}
///           [(x_i - x_{i+m/2-d}) + (x_{i+m} - x_{i+m/2+d})]^2 / (m/2 - d),
/// at tau = 0.75 m tau0; n = (N - m) m / 2 terms (Stable32's "#").
template <class T>
NaiveRow naive_theo1_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  if (m % 2 != 0 || m >= N) return {};
  const auto X = [&](std::int64_t k) {
    return static_cast<long double>(x[static_cast<std::size_t>(k)]);
  };
  const std::int64_t h = m / 2;
  long double s = 0;
  for (std::int64_t i = 0; i + m < N; ++i)
    for (std::int64_t d = 0; d < h; ++d) {
      const long double t = (X(i) - X(i + h - d)) + (X(i + m) - X(i + h + d));
      s += t * t / static_cast<long double>(h - d);
    }
  const long double tau = m * tau0;
  return {std::sqrt(s / (0.75L * (N - m) * tau * tau)), (N - m) * h};
}

/// ThêoH, SP1065 eqs. (31)-(32) (kernels/allan/theo.hpp theoh): OADEV for m < k =
/// floor(0.1 (N - 1)), Thêo1 times the mean OAVAR(9 + 3i) / Theo1(12 + 4i) ratio (i = 0 ..
/// floor(0.1 N / 3 - 3)) for even m >= 10 with 0.75 m >= k; n = 0 for any other m.
template <class T>
NaiveRow naive_theoh_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  const auto nbr = static_cast<std::int64_t>(std::floor(0.1L * N / 3 - 3));
  const std::int64_t k = (N - 1) / 10;
  if (nbr < 0) return {};
  if (m < k) return naive_oadev_phase(x, m, tau0, 1);
  if (m % 2 != 0 || m < 10 || m > N - 1 || 4 * k > 3 * m) return {};
  long double ratio = 0;
  for (std::int64_t i = 0; i <= nbr; ++i) {
    const long double a = naive_oadev_phase(x, 9 + 3 * i, tau0, 1).dev;
    const long double t = naive_theo1_phase(x, 12 + 4 * i, tau0).dev;
    ratio += a * a / (t * t);
  }
  NaiveRow r = naive_theo1_phase(x, m, tau0);
  r.dev *= std::sqrt(ratio / (nbr + 1));
  return r;
}

/// The half-average detrend of SP1065 sec. 5.2.12 (MTOT) and 5.2.14 (HTOT): the slope is the
/// difference of the means of the first and last floor(L/2) values of the window w over the
/// distance of their centres (L/2 for even L, (L+1)/2 for odd L); returns w minus slope * i.
inline std::vector<long double> naive_half_average_detrend(std::vector<long double> w) {
  const auto L = static_cast<std::int64_t>(w.size());
  const std::int64_t h = L / 2;
  long double a = 0, b = 0;
  for (std::int64_t i = 0; i < h; ++i) {
    a += w[static_cast<std::size_t>(i)];
    b += w[static_cast<std::size_t>(L - h + i)];
  }
  const long double slope = (b - a) / h / static_cast<long double>(L - h);
  for (std::int64_t i = 0; i < L; ++i)
    w[static_cast<std::size_t>(i)] -= slope * i;
  return w;
}

/// Mean over the 6m terms j of z_j^2, z_j = (S_j - 2 S_{j+m} + S_{j+2m}) / m with S_k the sum
/// of m consecutive values of the window extended to 9m points by uninverted even reflection
/// at both ends (SP1065 eqs. (27) and (29): the sequence w reversed, w, w reversed).
inline long double naive_reflected_mean_square(const std::vector<long double>& w, std::int64_t m) {
  const auto L = static_cast<std::int64_t>(w.size());  // 3m
  std::vector<long double> e;
  for (std::int64_t i = L - 1; i >= 0; --i)
    e.push_back(w[static_cast<std::size_t>(i)]);
  e.insert(e.end(), w.begin(), w.end());
  for (std::int64_t i = L - 1; i >= 0; --i)
    e.push_back(w[static_cast<std::size_t>(i)]);
  const auto S = [&](std::int64_t k) {
    long double s = 0;
    for (std::int64_t i = k; i < k + m; ++i)
      s += e[static_cast<std::size_t>(i)];
    return s;
  };
  long double sum = 0;
  for (std::int64_t j = 0; j < 6 * m; ++j) {
    const long double z = (S(j) - 2 * S(j + m) + S(j + 2 * m)) / m;
    sum += z * z;
  }
  return sum / (6 * m);
}

/// MTOTDEV, SP1065 eq. (27), p. 25 (Howe & Vernotte 1999): over the N - 3m + 1 windows of 3m
/// phase points, detrended by the half averages and reflected,
///   Mod Totvar = 1 / (2 tau^2 (N - 3m + 1)) sum_windows mean_j z_j^2.
template <class T>
NaiveRow naive_mtotdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  if (N - 3 * m + 1 < 1) return {};
  long double s = 0;
  for (std::int64_t n = 0; n + 3 * m <= N; ++n) {
    // Relative to the window's first point: a constant changes no z_j (it cancels in every
    // second difference, and its reflection is itself), and the long-double sums then stay of
    // the size of the window's excursion instead of the record's offset.
    std::vector<long double> w;
    for (std::int64_t t = 0; t < 3 * m; ++t)
      w.push_back(static_cast<long double>(x[static_cast<std::size_t>(n + t)]) -
                  static_cast<long double>(x[static_cast<std::size_t>(n)]));
    s += naive_reflected_mean_square(naive_half_average_detrend(w), m);
  }
  const long double tau = m * tau0;
  const std::int64_t M = N - 3 * m + 1;
  return {std::sqrt(s / (2 * tau * tau * M)), M};
}

/// HTOTDEV, SP1065 eq. (29), p. 27 (Howe, Beard, Greenhall, Riley 2001), on the N - 1
/// frequency averages y_i = (x_{i+1} - x_i) / tau0: over the N - 3m windows of 3m of them,
/// detrended and reflected, Htotvar = 1 / (6 (N - 3m)) sum_windows mean_j z_j^2. At m = 1 it is
/// OHDEV (SP1065 p. 27, as Stable32 does).
template <class T>
NaiveRow naive_htotdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  if (m == 1) return naive_hdev_phase(x, 1, tau0, 1);
  const auto N = static_cast<std::int64_t>(x.size());
  std::vector<long double> y;
  for (std::int64_t i = 0; i + 1 < N; ++i)
    y.push_back((static_cast<long double>(x[static_cast<std::size_t>(i + 1)]) -
                 static_cast<long double>(x[static_cast<std::size_t>(i)])) /
                tau0);
  const std::int64_t M = N - 3 * m;
  if (M < 1) return {};
  long double s = 0;
  for (std::int64_t n = 0; n < M; ++n) {
    std::vector<long double> w(y.begin() + n, y.begin() + n + 3 * m);
    s += naive_reflected_mean_square(naive_half_average_detrend(w), m);
  }
  return {std::sqrt(s / (6 * M)), M};
}

/// PDEV, Vernotte et al., Metrologia 53 (2016), eq. (18) in phase form (the parabolic
/// omega-counter variance, AllanTools' pdev): for m >= 2,
///   PVAR = 72 / (M m^4 tau^2) sum_{i=0}^{M-1} [sum_{k=0}^{m-1} ((m-1)/2 - k)(x_{i+k} -
///   x_{i+m+k})]^2
/// with M = N - 2m (Vernotte et al. 2020's count, as AllanTools; the last window of 2m points
/// is not used), and OADEV at m = 1.
template <class T>
NaiveRow naive_pdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  if (m == 1) return naive_oadev_phase(x, 1, tau0, 1);
  const auto N = static_cast<std::int64_t>(x.size());
  const std::int64_t M = N - 2 * m;
  if (M < 1) return {};
  long double s = 0;
  for (std::int64_t i = 0; i < M; ++i) {
    long double a = 0;
    for (std::int64_t k = 0; k < m; ++k)
      a +=
          ((m - 1) / 2.0L - k) * (static_cast<long double>(x[static_cast<std::size_t>(i + k)]) -
                                  static_cast<long double>(x[static_cast<std::size_t>(i + m + k)]));
    s += a * a;
  }
  const long double tau = m * tau0;
  return {std::sqrt(72 * s / (M * std::pow(static_cast<long double>(m), 4) * tau * tau)), M};
}

}  // namespace allanlot::test
