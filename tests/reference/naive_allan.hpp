// Naive O(N*m) implementations of the Allan-family statistics, straight from their NIST
// SP1065 definitions, in long double: the direct reference that the prefix-sum kernels are
// compared with (STYLE.md "Direct reference"). They share none of the kernels' tricks (no
// prefix sums, no mean removal).
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

/// OADEV (stride 1) or ADEV (stride m) from phase x_0..x_{N-1}, SP1065 eq. (11) p. 16 and
/// eq. (7) p. 14: sigma^2 = sum (x_{i+2m} - 2x_{i+m} + x_i)^2 / (2 tau^2 n).
inline NaiveRow naive_oadev_phase(const std::vector<double>& x, std::int64_t m, long double tau0,
                                  std::int64_t stride = 1) {
  const auto N = static_cast<std::int64_t>(x.size());
  long double s = 0;
  std::int64_t n = 0;
  for (std::int64_t i = 0; i + 2 * m < N; i += stride) {
    bool ok = true;
    for (std::int64_t k = i; k <= i + 2 * m; ++k)
      ok = ok && !std::isnan(x[k]);
    if (!ok) continue;
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

}  // namespace allanlot::test
