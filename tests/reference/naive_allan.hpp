// Naive O(N*m) implementations of the Allan-family statistics, straight from their NIST
// SP1065 definitions, in long double: the direct reference that the prefix-sum kernels are
// compared with (STYLE.md "Direct reference"). They share none of the kernels' tricks (no
// prefix sums, no mean removal).
//
// The phase-domain functions take double or long double samples (a long-double phase keeps
// the reference exact when the data carry a large offset).
//
// Gap rule, the same as the kernels': a term is skipped when any sample inside its span is
// missing (NaN), i.e. "the terms that touch a gap" are excluded.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

namespace allanlot::test {

struct NaiveRow {
  long double dev = 0;
  std::int64_t n = 0;
};

/// NaN counts before each index, so that "any NaN in x_a .. x_b" costs O(1) per term and the
/// references stay O(N) per m on long records.
template <class T>
std::vector<std::int64_t> nan_prefix(const std::vector<T>& x) {
  std::vector<std::int64_t> c(x.size() + 1, 0);
  for (std::size_t i = 0; i < x.size(); ++i)
    c[i + 1] = c[i] + (std::isnan(x[i]) ? 1 : 0);
  return c;
}

/// OADEV (stride 1) or ADEV (stride m) from phase x_0..x_{N-1}, SP1065 eq. (11) p. 16 and
/// eq. (7) p. 14: sigma^2 = sum (x_{i+2m} - 2x_{i+m} + x_i)^2 / (2 tau^2 n).
template <class T>
NaiveRow naive_oadev_phase(const std::vector<T>& x, std::int64_t m, long double tau0,
                           std::int64_t stride = 1) {
  const auto N = static_cast<std::int64_t>(x.size());
  long double s = 0;
  std::int64_t n = 0;
  const auto nans = nan_prefix(x);
  for (std::int64_t i = 0; i + 2 * m < N; i += stride) {
    if (nans[static_cast<std::size_t>(i + 2 * m + 1)] != nans[static_cast<std::size_t>(i)])
      continue;
    const long double d = static_cast<long double>(x[i + 2 * m]) -
                          2.0L * static_cast<long double>(x[i + m]) +
                          static_cast<long double>(x[i]);
    s += d * d;
    ++n;
  }
  const long double tau = m * tau0;
  return {n ? std::sqrt(s / (2 * tau * tau * n)) : 0.0L, n};
}

/// OADEV from rate samples y_0..y_{N-1} by explicit m-sample averages, SP1065 eq. (11) in
/// its frequency form: sigma^2 = sum (ybar_{i+m} - ybar_i)^2 / (2 n), ybar_i the average of
/// y_i .. y_{i+m-1}.
inline NaiveRow naive_oadev_rate(const std::vector<double>& y, std::int64_t m,
                                 std::int64_t stride = 1) {
  const auto N = static_cast<std::int64_t>(y.size());
  long double s = 0;
  std::int64_t n = 0;
  for (std::int64_t i = 0; i + 2 * m <= N; i += stride) {
    long double a = 0, b = 0;
    bool ok = true;
    for (std::int64_t k = 0; k < m; ++k) {
      ok = ok && !std::isnan(y[i + k]) && !std::isnan(y[i + m + k]);
      a += y[i + k];
      b += y[i + m + k];
    }
    if (!ok) continue;
    const long double d = (b - a) / m;
    s += d * d;
    ++n;
  }
  return {n ? std::sqrt(s / (2 * n)) : 0.0L, n};
}

/// MDEV from phase x_0..x_{N-1}, SP1065 eq. (14) p. 17, by explicit inner sums (O(N m)):
/// Mod sigma^2 = sum_j (sum_{i=j}^{j+m-1} (x_{i+2m} - 2x_{i+m} + x_i))^2 / (2 m^2 tau^2 n).
/// A term is skipped when any of x_j .. x_{j+3m-1} is NaN.
template <class T>
NaiveRow naive_mdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  long double s = 0;
  std::int64_t n = 0;
  const auto nans = nan_prefix(x);
  for (std::int64_t j = 0; j + 3 * m <= N; ++j) {
    if (nans[static_cast<std::size_t>(j + 3 * m)] != nans[static_cast<std::size_t>(j)]) continue;
    long double inner = 0;
    for (std::int64_t i = j; i < j + m; ++i) {
      inner += static_cast<long double>(x[i + 2 * m]) - 2.0L * static_cast<long double>(x[i + m]) +
               static_cast<long double>(x[i]);
    }
    s += inner * inner;
    ++n;
  }
  const long double tau = m * tau0;
  return {n ? std::sqrt(s / (2 * m * m * tau * tau * n)) : 0.0L, n};
}

/// TDEV = tau / sqrt(3) * MDEV, SP1065 eq. (16) p. 18.
template <class T>
NaiveRow naive_tdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  NaiveRow r = naive_mdev_phase(x, m, tau0);
  r.dev *= m * tau0 / std::sqrt(3.0L);
  return r;
}

/// OHDEV (stride 1) or HDEV (stride m), SP1065 eqs. (18) p. 21 and (17) p. 20:
/// H sigma^2 = sum (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i)^2 / (6 tau^2 n).
template <class T>
NaiveRow naive_hdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0,
                          std::int64_t stride = 1) {
  const auto N = static_cast<std::int64_t>(x.size());
  long double s = 0;
  std::int64_t n = 0;
  const auto nans = nan_prefix(x);
  for (std::int64_t i = 0; i + 3 * m < N; i += stride) {
    if (nans[static_cast<std::size_t>(i + 3 * m + 1)] != nans[static_cast<std::size_t>(i)])
      continue;
    const long double d =
        static_cast<long double>(x[i + 3 * m]) - 3.0L * static_cast<long double>(x[i + 2 * m]) +
        3.0L * static_cast<long double>(x[i + m]) - static_cast<long double>(x[i]);
    s += d * d;
    ++n;
  }
  const long double tau = m * tau0;
  return {n ? std::sqrt(s / (6 * tau * tau * n)) : 0.0L, n};
}

/// TOTDEV, SP1065 eq. (25) p. 23, on the doubly reflected sequence
/// x*_{1-j} = 2x_1 - x_{1+j}, x*_{N+j} = 2x_N - x_{N-j} (1-based), j = 1 .. N-2:
/// Tot var = sum_{i=2}^{N-1} (x*_{i-m} - 2x*_i + x*_{i+m})^2 / (2 tau^2 (N-2)).
/// No gaps (NaN) allowed; m <= (N-1)/2.
template <class T>
NaiveRow naive_totdev_phase(const std::vector<T>& x, std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  const auto at = [&](std::int64_t k) -> long double {  // x*_k, 0-based
    if (k < 0) return 2.0L * x[0] - static_cast<long double>(x[static_cast<std::size_t>(-k)]);
    if (k > N - 1)
      return 2.0L * x[static_cast<std::size_t>(N - 1)] -
             static_cast<long double>(x[static_cast<std::size_t>(2 * (N - 1) - k)]);
    return x[static_cast<std::size_t>(k)];
  };
  long double s = 0;
  for (std::int64_t i = 1; i <= N - 2; ++i) {
    const long double d = at(i - m) - 2.0L * at(i) + at(i + m);
    s += d * d;
  }
  const long double tau = m * tau0;
  return {std::sqrt(s / (2 * tau * tau * (N - 2))), N - 2};
}

/// MDEV as naive_mdev_phase, but with the inner sum carried from one j to the next
/// (adding x_{j+3m} - 3x_{j+2m} + 3x_{j+m} - x_j) in long double: O(N) instead of O(N m),
/// for records too long for the direct double loop. No gaps (NaN) allowed.
template <class T>
NaiveRow naive_mdev_phase_running(const std::vector<T>& x, std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  if (N < 3 * m) return {};
  const auto X = [&](std::int64_t k) {
    return static_cast<long double>(x[static_cast<std::size_t>(k)]);
  };
  long double inner = 0;
  for (std::int64_t i = 0; i < m; ++i)
    inner += X(i + 2 * m) - 2.0L * X(i + m) + X(i);
  long double s = inner * inner;
  std::int64_t n = 1;
  for (std::int64_t j = 0; j + 3 * m < N; ++j) {
    inner += X(j + 3 * m) - 3.0L * X(j + 2 * m) + 3.0L * X(j + m) - X(j);
    s += inner * inner;
    ++n;
  }
  const long double tau = m * tau0;
  return {std::sqrt(s / (2 * m * m * tau * tau * n)), n};
}

}  // namespace allanlot::test
