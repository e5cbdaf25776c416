// Least-squares pieces shared by the two equation (3) fits (kernels/model/fit.hpp in the Allan
// domain, kernels/model/psd_fit.hpp in the PSD domain): the active-set NNLS on the five squared
// coefficients and the per-term read-out of a fitted theta (detection, sigma, upper bound).
#pragma once

#include "kernels/model/fit.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <array>

namespace allanlot::kernels::detail {

/// Solves min || A x - b || over the columns marked in `use` (the others 0) with a
/// column-pivoting QR of the masked matrix (a zero column is ranked last and gets a zero
/// component). `masked` and `qr` are workspaces.
Eigen::Matrix<double, kNumTerms, 1> masked_ls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                              const std::array<bool, kNumTerms>& use,
                                              Eigen::MatrixXd& masked,
                                              Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr);

/// Lawson & Hanson's active-set NNLS ("Solving Least Squares Problems", 1974, ch. 23,
/// algorithm NNLS): min || A x - b || subject to x >= 0, for the 5-column (scaled) design.
Eigen::Matrix<double, kNumTerms, 1> nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                         Eigen::MatrixXd& masked,
                                         Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr);

/// Inverse of the standard normal CDF for p in (0.5, 1).
double normal_quantile(double p);

/// Fills value, detected, sigma and upper of `t` from its theta, theta_sigma, theta_free and
/// at_bound (see TermFit): detected when free and theta > detection_sigmas * theta_sigma
/// (a one-sided Wald test); sigma by first-order propagation through the square root when
/// detected, else sqrt(theta + theta_sigma) - sqrt(theta) (finite at zero); upper =
/// sqrt(max(theta_free, 0) + z_upper theta_sigma), z_upper the one-sided normal quantile.
void finish_term(TermFit& t, double detection_sigmas, double z_upper);

}  // namespace allanlot::kernels::detail
