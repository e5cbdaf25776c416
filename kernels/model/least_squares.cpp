// Least-squares pieces shared by the two eq. (3) fits; see detail/nnls.hpp.
#include "kernels/model/least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace allanlot::kernels::detail {

// Solves min || A x - b || over the columns marked in `use` (others 0) with a column-pivoting
// QR on the masked matrix (a zero column is ranked last and gets a zero component).
Eigen::Matrix<double, kNumTerms, 1> masked_ls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                              const std::array<bool, kNumTerms>& use,
                                              Eigen::MatrixXd& masked,
                                              Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr) {
  masked = a;
  for (int j = 0; j < kNumTerms; ++j)
    if (!use[static_cast<std::size_t>(j)]) masked.col(j).setZero();
  qr.compute(masked);
  Eigen::Matrix<double, kNumTerms, 1> x = qr.solve(b);
  for (int j = 0; j < kNumTerms; ++j)
    if (!use[static_cast<std::size_t>(j)]) x(j) = 0.0;
  return x;
}

// Lawson & Hanson's active-set NNLS (1974, ch. 23, algorithm NNLS) for the 5-column scaled
// design. The gradient tolerance is relative to |A| |b|, as in their implementation.
Eigen::Matrix<double, kNumTerms, 1> nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                         Eigen::MatrixXd& masked,
                                         Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr) {
  Eigen::Matrix<double, kNumTerms, 1> x = Eigen::Matrix<double, kNumTerms, 1>::Zero();
  std::array<bool, kNumTerms> passive{};
  std::array<bool, kNumTerms> refused{};
  const double tol = 1e-13 * a.norm() * b.norm();
  for (int outer = 0; outer < 4 * kNumTerms; ++outer) {
    const Eigen::Matrix<double, kNumTerms, 1> grad = a.transpose() * (b - a * x);
    int j_best = -1;
    for (int j = 0; j < kNumTerms; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      if (passive[ju] || refused[ju] || !(grad(j) > tol)) continue;
      if (j_best < 0 || grad(j) > grad(j_best)) j_best = j;
    }
    if (j_best < 0) break;
    passive[static_cast<std::size_t>(j_best)] = true;
    for (int inner = 0; inner < 4 * kNumTerms; ++inner) {
      const Eigen::Matrix<double, kNumTerms, 1> z = masked_ls(a, b, passive, masked, qr);
      bool feasible = true;
      for (int j = 0; j < kNumTerms; ++j)
        if (passive[static_cast<std::size_t>(j)] && !(z(j) > 0.0)) feasible = false;
      if (feasible) {
        x = z;
        break;
      }
      // Rounding can leave the column just added non-positive on its own: refuse it (it
      // cannot improve the fit) instead of cycling.
      if (!(z(j_best) > 0.0) && x(j_best) == 0.0) {
        passive[static_cast<std::size_t>(j_best)] = false;
        refused[static_cast<std::size_t>(j_best)] = true;
        break;
      }
      double step = 1.0;
      for (int j = 0; j < kNumTerms; ++j)
        if (passive[static_cast<std::size_t>(j)] && !(z(j) > 0.0))
          step = std::min(step, x(j) / (x(j) - z(j)));
      x += step * (z - x);
      for (int j = 0; j < kNumTerms; ++j)
        if (passive[static_cast<std::size_t>(j)] && !(x(j) > 0.0)) {
          passive[static_cast<std::size_t>(j)] = false;
          x(j) = 0.0;
        }
    }
    // A successful addition changes the gradient: refused columns may be tried again.
    if (passive[static_cast<std::size_t>(j_best)]) refused = std::array<bool, kNumTerms>{};
  }
  return x;
}

// Inverse of the standard normal CDF for p in (0.5, 1) by Newton's method on erfc (the
// quantiles needed here are 0.84 .. 0.999).
double normal_quantile(double p) {
  double z = 1.0;
  for (int it = 0; it < 50; ++it) {
    const double cdf = 0.5 * std::erfc(-z / std::numbers::sqrt2);
    const double pdf = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
    const double dz = (cdf - p) / pdf;
    z -= dz;
    if (std::abs(dz) < 1e-14) break;
  }
  return z;
}

void finish_term(TermFit& t, double detection_sigmas, double z_upper) {
  t.value = std::sqrt(std::max(t.theta, 0.0));
  t.detected = !t.at_bound && t.theta > detection_sigmas * t.theta_sigma;
  t.sigma =
      t.detected ? t.theta_sigma / (2.0 * t.value) : std::sqrt(t.theta + t.theta_sigma) - t.value;
  t.upper = std::sqrt(std::max(t.theta_free, 0.0) + z_upper * t.theta_sigma);
}

}  // namespace allanlot::kernels::detail
