// Least squares of the noise model, one implementation for every caller: the active-set NNLS
// (the two eq. (3) fits, kernels/model/fit.hpp in the Allan domain and
// kernels/model/psd_fit.hpp in the PSD domain, and diagnose's component fit), the weighted,
// column-scaled design and its reweighting that the two eq. (3) fits share, the sandwich
// estimator of their covariance, and the per-term read-out of a fitted theta (detection, sigma,
// upper bound).
#pragma once

#include "kernels/model/terms.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <array>
#include <cmath>

namespace allanlot::kernels {

/// One term of eq. (3) as fitted.
struct TermFit {
  // Coefficient, >= 0, in the unit of docs/formats.md "Units and conventions" (u/s, u/s^0.5,
  // u, u*s^0.5, u*s).
  double value = 0.0;
  // 1-sigma of value: sigma_theta / (2 value) (first-order propagation) when detected;
  // otherwise sqrt(theta + sigma_theta) - sqrt(theta), finite also at value = 0.
  double sigma = 0.0;
  bool detected = false;  // theta > detection_sigmas * sigma_theta (one-sided Wald test)
  // One-sided upper bound on value at FitOptions::upper_confidence:
  // sqrt(max(theta_free, 0) + z sigma_theta), z the normal quantile (1.645 at 95 %). Clipping
  // theta_free at zero makes the bound conservative when the data pull the term negative.
  double upper = 0.0;
  double theta = 0.0;        // value^2, the fitted (constrained) parameter, u^2 * s^k
  double theta_sigma = 0.0;  // 1-sigma of theta (sandwich; see kernels/model/fit.hpp)
  // theta with this term allowed to go negative (the other terms as in the fit): equal to
  // theta when the term is free, <= 0 when the constraint holds it at zero.
  double theta_free = 0.0;
  bool at_bound = false;  // held at zero by the non-negativity constraint
};

namespace detail {

using Theta = Eigen::Matrix<double, kNumTerms, 1>;
using TermCov = Eigen::Matrix<double, kNumTerms, kNumTerms>;
using Estimator = Eigen::Matrix<double, kNumTerms, Eigen::Dynamic>;
using Qr = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;

/// How a caller runs Lawson & Hanson's active-set NNLS. Each caller keeps the choices it was
/// validated with, because each changes the rounding of results that bit-identity tests pin.
/// The iteration limits are per_column * (number of columns) + extra.
struct NnlsOptions {
  double relative_tolerance = 1e-13;  // gradient tolerance relative to |A| |b|
  double b_norm_floor = 0.0;          // > 0: |b| is taken as at least this
  int outer_per_column = 4, outer_extra = 0;
  int inner_per_column = 4, inner_extra = 0;
  double drop_level = 0.0;  // a passive x_j that a step leaves <= this leaves the passive set
  bool drop_nan = true;     // and so does a NaN one
  // Rounding can leave the column just added non-positive on its own; refuse it (it cannot
  // improve the fit) instead of cycling until the limit.
  bool refuse_stalled = true;
};

/// The eq. (3) fits' choices (the defaults): tolerance 1e-13 |A| |b| as in Lawson & Hanson's
/// implementation, stalled columns refused.
inline constexpr NnlsOptions kEq3Nnls{};

/// min || A x - b || subject to x >= 0 for the 5-column (scaled) eq. (3) design (Lawson &
/// Hanson, "Solving Least Squares Problems", 1974, ch. 23, algorithm NNLS). Each subproblem is
/// a column-pivoting QR of A with the inactive columns zeroed (a zero column is ranked last and
/// gets a zero component); `masked` and `qr` are the caller's workspaces.
Theta nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const NnlsOptions& options,
           Eigen::MatrixXd& masked, Qr& qr);

/// The same algorithm for any number of columns, each subproblem a fresh column-pivoting QR of
/// the active columns alone.
Eigen::VectorXd nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                     const NnlsOptions& options);

/// Factors A with the columns not marked in `use` zeroed: masked = A so masked, then
/// qr.compute(masked).
void factor_masked(const Eigen::MatrixXd& a, const std::array<bool, kNumTerms>& use,
                   Eigen::MatrixXd& masked, Qr& qr);

/// The eq. (3) design as both fits solve it: row i weighted by sw_i = sqrt(edf_i / 2) / model_i,
/// the square root of edf / (2 model^2), the inverse variance of a chi-square estimate under the
/// model; each column then scaled to unit norm (the raw columns span up to 24 orders of
/// magnitude over 6 decades of tau), so that the scaled solution z gives theta = col_scale z.
struct WeightedDesign {
  Eigen::VectorXd sw;  // square roots of the row weights
  Eigen::MatrixXd xs;  // diag(sw) X, column j times col_scale(j)
  Theta col_scale;     // 1 / the column's norm (1 for a zero column)
  Eigen::VectorXd bs;  // diag(sw) y

  void build(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& edf,
             const Eigen::VectorXd& model);
};

/// The reweighting of the two eq. (3) fits.
struct Reweighting {
  double rank_threshold = 1e-10;  // ColPivHouseholderQR threshold on the scaled design
  int max_iterations = 500;
  double tolerance = 1e-10;  // stop when the model curve changes by less than this (relative)
  double model_floor = 0.0;  // > 0: the model is kept at least this (for the next weights)
};

struct ReweightedNnls {
  Theta theta = Theta::Zero();
  int rank = 0;  // of the first weighted design; < kNumTerms: nothing was solved
  int iterations = 0;
  bool converged = false;
};

/// Iteratively reweighted NNLS of theta on y = X theta: the weights of each solve come from the
/// model of the previous one (`model` holds the first model on entry and the last on return),
/// not from the estimates, which would favour the estimates that fell low. On return `design`
/// holds the weights of the final model and `qr` its last factorization.
ReweightedNnls reweighted_nnls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                               const Eigen::VectorXd& edf, Eigen::VectorXd& model,
                               const Reweighting& settings, WeightedDesign& design,
                               Eigen::MatrixXd& masked, Qr& qr);

/// Copies the rank and the iterations of `solved` into a fit's result (the Allan fit's or the
/// PSD fit's); false, with the result's status set to `rank_deficient`, when the weighted design
/// did not have full rank and nothing was solved.
template <class Result, class Status>
bool take_solution(Result& res, const ReweightedNnls& solved, Status rank_deficient) {
  res.rank = solved.rank;
  if (res.rank < kNumTerms) {
    res.status = rank_deficient;
    return false;
  }
  res.iterations = solved.iterations;
  return true;
}

/// The estimator matrix of the weighted fit on the columns marked in `use`,
/// A = D (Xs_F^T Xs_F)^-1 Xs_F^T diag(sw) (D = diag(col_scale); rows of unused columns zero),
/// so that theta_F = A y. Row i of A^T solves the least squares with right-hand side sw_i e_i;
/// column by column (a vector right-hand side each) keeps every operation a serial
/// matrix-vector one, the same for any thread count.
void estimator_matrix(const WeightedDesign& design, const std::array<bool, kNumTerms>& use,
                      Eigen::MatrixXd& masked, Qr& qr, Estimator& amat);

/// Inverse of the standard normal CDF for p in (0.5, 1).
double normal_quantile(double p);

/// Fills value, detected, sigma and upper of `t` from its theta, theta_sigma, theta_free and
/// at_bound (see TermFit): detected when free and theta > detection_sigmas * theta_sigma
/// (a one-sided Wald test); sigma by first-order propagation through the square root when
/// detected, else sqrt(theta + theta_sigma) - sqrt(theta) (finite at zero); upper =
/// sqrt(max(theta_free, 0) + z_upper theta_sigma), z_upper the one-sided normal quantile.
void finish_term(TermFit& t, double detection_sigmas, double z_upper);

/// Every term of a weighted eq. (3) fit: a term is free when theta_j > 0. Its theta_sigma comes
/// from the sandwich covariance A Sigma A^T of the estimator on the free columns; a term held
/// at zero is released alone (the others as they are, the same weights) for its theta_free and
/// theta_sigma. `sandwich(amat, cov)` computes cov = A Sigma A^T in the caller's own operation
/// order. On return `a_free` holds A on the free columns and theta_cov its covariance; returns
/// the number of free terms.
template <class Sandwich>
int fit_terms(const Theta& theta, const Eigen::VectorXd& y, const WeightedDesign& design,
              double detection_sigmas, double upper_confidence, Sandwich&& sandwich,
              Eigen::MatrixXd& masked, Qr& qr, std::array<TermFit, kNumTerms>& terms,
              TermCov& theta_cov, Estimator& a_free) {
  std::array<bool, kNumTerms> free{};
  int n_free = 0;
  for (int j = 0; j < kNumTerms; ++j) {
    free[static_cast<std::size_t>(j)] = theta(j) > 0.0;
    n_free += theta(j) > 0.0 ? 1 : 0;
  }
  estimator_matrix(design, free, masked, qr, a_free);
  sandwich(a_free, theta_cov);
  const double z_up = normal_quantile(upper_confidence);
  Estimator a_released;
  for (int j = 0; j < kNumTerms; ++j) {
    TermFit& t = terms[static_cast<std::size_t>(j)];
    t.theta = theta(j);
    t.at_bound = !free[static_cast<std::size_t>(j)];
    if (!t.at_bound) {
      t.theta_free = theta(j);
      t.theta_sigma = std::sqrt(std::max(theta_cov(j, j), 0.0));
    } else {
      std::array<bool, kNumTerms> use = free;
      use[static_cast<std::size_t>(j)] = true;
      TermCov cov;
      estimator_matrix(design, use, masked, qr, a_released);
      sandwich(a_released, cov);
      t.theta_free = a_released.row(j).dot(y);
      t.theta_sigma = std::sqrt(std::max(cov(j, j), 0.0));
    }
    finish_term(t, detection_sigmas, z_up);
  }
  return n_free;
}

}  // namespace detail
}  // namespace allanlot::kernels
