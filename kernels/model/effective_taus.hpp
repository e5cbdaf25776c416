// The effective number of independent taus of a correlated Allan curve, from the model
// covariance of its estimates (OavarCovariance, fit.hpp): Satterthwaite's n_eff (Box 1954,
// "Some theorems on quadratic forms applied in the study of analysis of variance problems",
// Ann. Math. Stat. 25), n_eff = P^2 / sum_ij C_ij^2 with C the correlation matrix, which
// matches the mean and variance of a sum of P correlated z^2 to a scaled chi-square with n_eff
// degrees of freedom. Shared by diagnose's criterion and analyze's filter detection.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace allanlot::kernels {

/// n_eff of covariance `s` (P x P), clamped to [1, P]; 0 when `s` is empty, not finite or has
/// a variance that is not positive (then the caller's fallback applies).
inline double effective_taus_of(const Eigen::MatrixXd& s) {
  const auto p = static_cast<double>(s.rows());
  if (s.rows() == 0 || s.rows() != s.cols() || !s.allFinite()) return 0.0;
  double sum = 0.0;
  for (Eigen::Index i = 0; i < s.rows(); ++i)
    for (Eigen::Index j = 0; j < s.cols(); ++j) {
      const double d = s(i, i) * s(j, j);
      if (!(d > 0.0)) return 0.0;
      const double c = s(i, j) / std::sqrt(d);
      sum += c * c;
    }
  return sum > 0.0 ? std::clamp(p * p / sum, 1.0, p) : 0.0;
}

}  // namespace allanlot::kernels
