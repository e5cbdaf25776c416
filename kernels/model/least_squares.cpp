// Least squares of the noise model; see least_squares.hpp.
#include "kernels/model/least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace allanlot::kernels::detail {
namespace {

// Subproblem of the fits: the caller's QR of the masked matrix. Returns z with zeros outside
// the passive set; `feasible` when every passive component is > 0.
struct MaskedSubproblem {
  Eigen::MatrixXd& masked;
  Qr& qr;

  Theta operator()(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                   const std::vector<char>& passive, bool& feasible) {
    std::array<bool, kNumTerms> use{};
    for (int j = 0; j < kNumTerms; ++j)
      use[static_cast<std::size_t>(j)] = passive[static_cast<std::size_t>(j)] != 0;
    factor_masked(a, use, masked, qr);
    Theta z = qr.solve(b);
    feasible = true;
    for (int j = 0; j < kNumTerms; ++j) {
      if (!use[static_cast<std::size_t>(j)])
        z(j) = 0.0;
      else if (!(z(j) > 0.0))
        feasible = false;
    }
    return z;
  }
};

// Subproblem on the passive columns alone, a fresh QR each.
struct CompactSubproblem {
  Eigen::VectorXd operator()(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                             const std::vector<char>& passive, bool& feasible) const {
    const Eigen::Index n = a.cols();
    std::vector<Eigen::Index> cols;
    for (Eigen::Index j = 0; j < n; ++j)
      if (passive[static_cast<std::size_t>(j)]) cols.push_back(j);
    Eigen::MatrixXd sub(a.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k)
      sub.col(static_cast<Eigen::Index>(k)) = a.col(cols[k]);
    const Eigen::VectorXd zs = sub.colPivHouseholderQr().solve(b);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    feasible = true;
    for (std::size_t k = 0; k < cols.size(); ++k) {
      z(cols[k]) = zs(static_cast<Eigen::Index>(k));
      feasible = feasible && zs(static_cast<Eigen::Index>(k)) > 0.0;
    }
    return z;
  }
};

// Lawson & Hanson's active-set NNLS (1974, ch. 23, algorithm NNLS). Vector is the type of x
// (fixed 5 for the fits, dynamic for diagnose): it decides how Eigen evaluates A x, so each
// caller keeps its own to keep its rounding.
template <class Vector, class Subproblem>
Vector active_set(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const NnlsOptions& o,
                  Subproblem&& solve) {
  const Eigen::Index n = a.cols();
  const auto nu = static_cast<std::size_t>(n);
  Vector x = Vector::Zero(n);
  std::vector<char> passive(nu, 0), refused(nu, 0);
  const double b_norm = o.b_norm_floor > 0.0 ? std::max(o.b_norm_floor, b.norm()) : b.norm();
  const double tol = o.relative_tolerance * a.norm() * b_norm;
  const int max_outer = o.outer_per_column * static_cast<int>(n) + o.outer_extra;
  const int max_inner = o.inner_per_column * static_cast<int>(n) + o.inner_extra;
  const auto leaves = [&](double v) {
    return o.drop_nan ? !(v > o.drop_level) : v <= o.drop_level;
  };
  for (int outer = 0; outer < max_outer; ++outer) {
    const Vector grad = a.transpose() * (b - a * x);
    Eigen::Index j_best = -1;
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      if (passive[ju] || refused[ju] || !(grad(j) > tol)) continue;
      if (j_best < 0 || grad(j) > grad(j_best)) j_best = j;
    }
    if (j_best < 0) break;
    const auto best = static_cast<std::size_t>(j_best);
    passive[best] = 1;
    for (int inner = 0; inner < max_inner; ++inner) {
      bool feasible = false;
      const Vector z = solve(a, b, passive, feasible);
      if (feasible) {
        x = z;
        break;
      }
      if (o.refuse_stalled && !(z(j_best) > 0.0) && x(j_best) == 0.0) {
        passive[best] = 0;
        refused[best] = 1;
        break;
      }
      double step = 1.0;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && !(z(j) > 0.0))
          step = std::min(step, x(j) / (x(j) - z(j)));
      x += step * (z - x);
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && leaves(x(j))) {
          passive[static_cast<std::size_t>(j)] = 0;
          x(j) = 0.0;
        }
    }
    // A successful addition changes the gradient: refused columns may be tried again.
    if (passive[best]) std::fill(refused.begin(), refused.end(), 0);
  }
  return x;
}

}  // namespace

Theta nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const NnlsOptions& options,
           Eigen::MatrixXd& masked, Qr& qr) {
  return active_set<Theta>(a, b, options, MaskedSubproblem{masked, qr});
}

Eigen::VectorXd nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                     const NnlsOptions& options) {
  return active_set<Eigen::VectorXd>(a, b, options, CompactSubproblem{});
}

void factor_masked(const Eigen::MatrixXd& a, const std::array<bool, kNumTerms>& use,
                   Eigen::MatrixXd& masked, Qr& qr) {
  masked = a;
  for (int j = 0; j < kNumTerms; ++j)
    if (!use[static_cast<std::size_t>(j)]) masked.col(j).setZero();
  qr.compute(masked);
}

void WeightedDesign::build(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                           const Eigen::VectorXd& edf, const Eigen::VectorXd& model) {
  const Eigen::Index p = x.rows();
  sw.resize(p);
  for (Eigen::Index i = 0; i < p; ++i)
    sw(i) = std::sqrt(0.5 * edf(i)) / model(i);
  xs = sw.asDiagonal() * x;
  for (int j = 0; j < kNumTerms; ++j) {
    const double nrm = xs.col(j).norm();
    col_scale(j) = nrm > 0.0 ? 1.0 / nrm : 1.0;
    xs.col(j) *= col_scale(j);
  }
  bs = sw.cwiseProduct(y);
}

ReweightedNnls reweighted_nnls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                               const Eigen::VectorXd& edf, Eigen::VectorXd& model,
                               const Reweighting& settings, WeightedDesign& design,
                               Eigen::MatrixXd& masked, Qr& qr) {
  ReweightedNnls out;
  const Eigen::Index p = x.rows();
  design.build(x, y, edf, model);
  qr.setThreshold(settings.rank_threshold);
  qr.compute(design.xs);
  out.rank = static_cast<int>(qr.rank());
  if (out.rank < kNumTerms) return out;
  for (int it = 1; it <= settings.max_iterations; ++it) {
    out.iterations = it;
    const Theta z = nnls(design.xs, design.bs, kEq3Nnls, masked, qr);
    out.theta = design.col_scale.cwiseProduct(z);
    const Eigen::VectorXd next = x * out.theta;
    double change = 0.0;
    for (Eigen::Index i = 0; i < p; ++i)
      change = std::max(change, std::abs(next(i) / model(i) - 1.0));
    if (settings.model_floor > 0.0)
      model = next.cwiseMax(settings.model_floor);
    else
      model = next;
    if (change <= settings.tolerance) {
      out.converged = true;
      break;
    }
    design.build(x, y, edf, model);
  }
  // The weights of the last solve: rebuild so that they and the final model agree.
  design.build(x, y, edf, model);
  return out;
}

void estimator_matrix(const WeightedDesign& design, const std::array<bool, kNumTerms>& use,
                      Eigen::MatrixXd& masked, Qr& qr, Estimator& amat) {
  const Eigen::Index p = design.xs.rows();
  factor_masked(design.xs, use, masked, qr);
  amat.resize(kNumTerms, p);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(p);
  for (Eigen::Index i = 0; i < p; ++i) {
    e(i) = design.sw(i);
    const Theta col = qr.solve(e);
    e(i) = 0.0;
    for (int j = 0; j < kNumTerms; ++j)
      amat(j, i) = use[static_cast<std::size_t>(j)] ? col(j) * design.col_scale(j) : 0.0;
  }
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
