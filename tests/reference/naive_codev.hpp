// Naive references of the two-recording statistics, straight from their definitions in long
// double (docs/statistics.md "Two recordings: gcodev and the three-cornered hat"): the
// Groslambert covariance as a plain sum of products of second differences, and the
// three-cornered hat from naive_oadev_phase of the three pairs. They share none of the kernels'
// machinery (no PhaseData, no mean removal, no chunking).
#pragma once

#include "reference/naive_allan.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace allanlot::test {

/// The Groslambert covariance (a variance, signed) of phase records x, y (equal length) and its
/// terms: sum_i (x_{i+2m} - 2x_{i+m} + x_i)(y_{i+2m} - 2y_{i+m} + y_i) / (2 tau^2 n), a term
/// skipped when any of x_i .. x_{i+2m} or y_i .. y_{i+2m} is NaN.
struct NaiveCov {
  long double var = 0;
  std::int64_t n = 0;
};

inline NaiveCov naive_gcov_phase(const std::vector<double>& x, const std::vector<double>& y,
                                 std::int64_t m, long double tau0) {
  const auto N = static_cast<std::int64_t>(x.size());
  const auto nx = nan_prefix(x), ny = nan_prefix(y);
  long double s = 0;
  std::int64_t n = 0;
  for (std::int64_t i = 0; i + 2 * m < N; ++i) {
    const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(i + 2 * m + 1);
    if (nx[b] != nx[a] || ny[b] != ny[a]) continue;
    const auto d = [i, m](const std::vector<double>& v) {
      return static_cast<long double>(v[i + 2 * m]) - 2.0L * static_cast<long double>(v[i + m]) +
             static_cast<long double>(v[i]);
    };
    s += d(x) * d(y);
    ++n;
  }
  const long double tau = m * tau0;
  return {n ? s / (2 * tau * tau * n) : 0.0L, n};
}

/// The three-cornered-hat variances of clocks A, B, C from the pair records AB, BC, CA (Gray &
/// Allan 1974): A = (AB + CA - BC) / 2 and its rotations, of the pairs' naive OAVAR.
inline std::array<long double, 3> naive_hat_phase(const std::vector<double>& ab,
                                                  const std::vector<double>& bc,
                                                  const std::vector<double>& ca, std::int64_t m,
                                                  long double tau0) {
  const long double s_ab = std::pow(naive_oadev_phase(ab, m, tau0).dev, 2.0L);
  const long double s_bc = std::pow(naive_oadev_phase(bc, m, tau0).dev, 2.0L);
  const long double s_ca = std::pow(naive_oadev_phase(ca, m, tau0).dev, 2.0L);
  return {0.5L * (s_ab + s_ca - s_bc), 0.5L * (s_ab + s_bc - s_ca), 0.5L * (s_bc + s_ca - s_ab)};
}

/// The N-cornered-hat variances of N clocks from their N(N-1)/2 pair records in pair order (AB AC
/// ... BC ...): the least-squares solution of s_ij = v_i + v_j for the pairs' naive OAVAR s
/// (Gray & Allan 1974), by the normal equations (A^T A) v = A^T s solved by Gaussian elimination
/// with partial pivoting in long double: no closed form, no weights.
inline std::vector<long double> naive_n_hat_phase(const std::vector<std::vector<double>>& pairs,
                                                  std::size_t n_clocks, std::int64_t m,
                                                  long double tau0) {
  std::vector<std::vector<long double>> a(n_clocks, std::vector<long double>(n_clocks + 1, 0.0L));
  std::size_t p = 0;
  for (std::size_t i = 0; i < n_clocks; ++i)
    for (std::size_t j = i + 1; j < n_clocks; ++j, ++p) {
      const long double s = std::pow(naive_oadev_phase(pairs[p], m, tau0).dev, 2.0L);
      for (const std::size_t r : {i, j}) {  // row (0..1..) of A has ones at i and j
        a[r][i] += 1.0L;
        a[r][j] += 1.0L;
        a[r][n_clocks] += s;
      }
    }
  for (std::size_t c = 0; c < n_clocks; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < n_clocks; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[piv][c])) piv = r;
    std::swap(a[c], a[piv]);
    for (std::size_t r = 0; r < n_clocks; ++r) {
      if (r == c) continue;
      const long double f = a[r][c] / a[c][c];
      for (std::size_t k = c; k <= n_clocks; ++k)
        a[r][k] -= f * a[c][k];
    }
  }
  std::vector<long double> v(n_clocks);
  for (std::size_t c = 0; c < n_clocks; ++c)
    v[c] = a[c][n_clocks] / a[c][c];
  return v;
}

}  // namespace allanlot::test
