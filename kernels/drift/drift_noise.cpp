// The noise model behind a drift's sigma (drift.hpp): its three levels from the residuals'
// overlapping Allan variance, and the variance of a linear functional of the samples under it.
#include "kernels/allan/allan.hpp"
#include "kernels/drift/drift.hpp"
#include "kernels/model/least_squares.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace allanlot::kernels {

double functional_variance(std::span<const double> v, std::span<const double> u,
                           const DriftNoise& noise) {
  long double uu = 0, vv = 0, tails = 0, tail = 0;
  for (const double x : u)
    uu += static_cast<long double>(x) * x;
  for (const double x : v)
    vv += static_cast<long double>(x) * x;
  // Random-walk FM: y_j = sum_{k<=j} r_k, so sum_j v_j y_j = sum_k r_k (sum_{j>=k} v_j).
  for (std::size_t k = v.size(); k-- > 0;) {
    tail += v[k];
    tails += tail * tail;
  }
  return static_cast<double>(noise.white_pm * uu + noise.white_fm * vv + noise.rw_fm * tails);
}

DriftNoise fit_drift_noise(std::span<const double> residuals, DataType type, double tau0_s) {
  const PhaseData phase = make_phase(residuals, type, 1.0 / tau0_s, 1);
  const std::int64_t n = phase.n_points() - 1;
  std::vector<std::int64_t> ms;
  for (std::int64_t m = 1; 10 * m <= n; m *= 2)
    ms.push_back(m);
  if (ms.empty()) return {};
  const StatResult r = oadev(phase, ms, 1);
  const auto rows = static_cast<Eigen::Index>(r.size());
  Eigen::MatrixXd a(rows, 3);
  Eigen::VectorXd b(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double tau = r.tau_s[k];
    const double avar = r.dev[k] * r.dev[k];
    // Each row relative to its own level, weighted by the square root of its independent
    // averages n/m: a tau's Allan variance scatters by about sqrt(2 / (n/m)) of itself (the
    // overlapping terms of one tau are correlated over m samples).
    const double dof = std::max(1.0, static_cast<double>(r.n[k]) / static_cast<double>(r.m[k]));
    const double w = avar > 0 ? std::sqrt(dof / 2) / avar : 0.0;
    a(i, 0) = w * 3 / (tau * tau);
    a(i, 1) = w * tau0_s / tau;
    const double m = static_cast<double>(r.m[k]);
    a(i, 2) = w * (2 * m * m + 1) / (6 * m);
    b(i) = w * avar;
  }
  DriftNoise noise;
  if (rows == 0) return noise;
  // Columns scaled to unit norm for the NNLS, then scaled back.
  Eigen::VectorXd scale(3);
  for (int c = 0; c < 3; ++c) {
    scale(c) = a.col(c).norm() > 0 ? a.col(c).norm() : 1.0;
    a.col(c) /= scale(c);
  }
  const Eigen::VectorXd x = detail::nnls(a, b, detail::NnlsOptions{});
  noise.white_pm = x(0) / scale(0);
  noise.white_fm = x(1) / scale(1);
  noise.rw_fm = x(2) / scale(2);
  // The random-walk level at its estimate plus one standard error: a drift's uncertainty rests
  // on the record's lowest frequencies, which its longest taus measure with a few degrees of
  // freedom, and the estimate alone (often clipped to zero where the walk is barely visible)
  // gave 3-sigma misses in 9 % of simulated clocks (docs/validation/2026-11-28-drift.md).
  if (rows < 3) return noise;
  const Eigen::MatrixXd cov = (a.transpose() * a).inverse();
  if (std::isfinite(cov(2, 2)) && cov(2, 2) > 0) noise.rw_fm += std::sqrt(cov(2, 2)) / scale(2);
  return noise;
}

}  // namespace allanlot::kernels
