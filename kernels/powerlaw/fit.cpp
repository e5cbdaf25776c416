#include "kernels/powerlaw/fit.hpp"

#include "kernels/model/fit.hpp"
#include "kernels/model/least_squares.hpp"
#include "kernels/powerlaw/theory.hpp"

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace allanlot::kernels::powerlaw {
namespace {

bool usable(const StatResult& s, std::size_t i) {
  return i < s.edf.size() && std::isfinite(s.dev[i]) && s.dev[i] >= 0.0 &&
         std::isfinite(s.edf[i]) && s.edf[i] > 0.0 && s.n[i] >= 1 && s.m[i] >= 1;
}

// The rows of the fit: the usable OADEV rows, then the usable MDEV rows at an m of theirs
// (avar_row: the index of that OADEV row).
struct Rows {
  std::vector<std::int64_t> m, n;
  std::vector<double> tau, var, edf;
  std::vector<std::size_t> mdev_row;  // per MDEV row, its OADEV row
  std::vector<double> mdev_tau, mdev_var, mdev_edf;
};

Rows select_rows(const StatResult& oadev, const StatResult* mdev) {
  Rows r;
  for (std::size_t i = 0; i < oadev.size(); ++i) {
    if (!usable(oadev, i)) continue;
    r.m.push_back(oadev.m[i]);
    r.n.push_back(oadev.n[i]);
    r.tau.push_back(oadev.tau_s[i]);
    r.var.push_back(oadev.dev[i] * oadev.dev[i]);
    r.edf.push_back(oadev.edf[i]);
  }
  if (mdev == nullptr) return r;
  std::size_t k = 0;
  for (std::size_t i = 0; i < mdev->size(); ++i) {
    if (!usable(*mdev, i)) continue;
    while (k < r.m.size() && r.m[k] < mdev->m[i])
      ++k;
    if (k == r.m.size()) break;
    if (r.m[k] != mdev->m[i]) continue;
    r.mdev_row.push_back(k);
    r.mdev_tau.push_back(mdev->tau_s[i]);
    r.mdev_var.push_back(mdev->dev[i] * mdev->dev[i]);
    r.mdev_edf.push_back(mdev->edf[i]);
  }
  return r;
}

// eq. (3)'s squared coefficients (R^2, K^2, B^2, N^2, Q^2) of the same Gaussian noise, for
// OavarCovariance (see the header): flicker PM as white PM of its Allan variance at tau_first.
std::array<double, 5> eq3_theta(const detail::Theta& h, double tau0_s, double tau_first) {
  const Eq3Squares e = eq3_squares(h(0), h(2), h(3), h(4), tau0_s);
  const double q2 = e.q2 + h(1) * avar_per_h(1, tau_first, tau0_s) * tau_first * tau_first / 3.0;
  return {0.0, e.k2, e.b2, e.n2, q2};
}

// Sigma of the stacked rows (see the header): [S; D] C [S D], C the AVAR correlation.
Eigen::MatrixXd row_covariance(const Eigen::MatrixXd& sigma_a, const Rows& r,
                               const Eigen::VectorXd& model) {
  const auto p = static_cast<Eigen::Index>(r.m.size());
  const auto q = static_cast<Eigen::Index>(r.mdev_row.size());
  Eigen::VectorXd scale(p + q);
  Eigen::VectorXi base(p + q);
  for (Eigen::Index i = 0; i < p; ++i) {
    scale(i) = std::sqrt(std::max(sigma_a(i, i), 0.0));
    base(i) = static_cast<int>(i);
  }
  for (Eigen::Index k = 0; k < q; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    scale(p + k) = std::sqrt(2.0 / r.mdev_edf[ku]) * model(p + k);
    base(p + k) = static_cast<int>(r.mdev_row[ku]);
  }
  Eigen::MatrixXd out(p + q, p + q);
  for (Eigen::Index i = 0; i < p + q; ++i)
    for (Eigen::Index j = 0; j < p + q; ++j) {
      const Eigen::Index a = base(i), b = base(j);
      const double da = scale(a), db = scale(b);
      const double c = (da > 0.0 && db > 0.0) ? sigma_a(a, b) / (da * db) : (a == b ? 1.0 : 0.0);
      out(i, j) = c * scale(i) * scale(j);
    }
  return out;
}

}  // namespace

std::string_view status_name(Status s) {
  switch (s) {
  case Status::Ok:
    return "ok";
  case Status::NoData:
    return "no_data";
  case Status::RankDeficient:
    return "rank_deficient";
  case Status::NoConvergence:
    return "no_convergence";
  }
  return "unknown";
}

double model_avar(const std::array<double, kNumLevels>& h, double tau_s, double tau0_s) {
  double v = 0.0;
  for (std::size_t j = 0; j < kNumLevels; ++j)
    v += h[j] * avar_per_h(kAlphas[j], tau_s, tau0_s);
  return v;
}

double model_mvar(const std::array<double, kNumLevels>& h, double tau_s, double tau0_s) {
  double v = 0.0;
  for (std::size_t j = 0; j < kNumLevels; ++j)
    v += h[j] * mvar_per_h(kAlphas[j], tau_s, tau0_s);
  return v;
}

Result fit(const StatResult& oadev, const StatResult* mdev, double tau0_s, const Options& options) {
  if (!(tau0_s > 0.0) || !std::isfinite(tau0_s))
    throw std::invalid_argument("powerlaw::fit: tau0_s must be finite and > 0");
  Result res;
  for (std::size_t j = 0; j < kNumLevels; ++j)
    res.levels[j].alpha = kAlphas[j];
  const Rows r = select_rows(oadev, mdev);
  const auto p = static_cast<Eigen::Index>(r.m.size());
  const auto q = static_cast<Eigen::Index>(r.mdev_row.size());
  double y_min_pos = std::numeric_limits<double>::infinity();
  for (const double v : r.var)
    if (v > 0.0) y_min_pos = std::min(y_min_pos, v);
  if (p == 0 || !std::isfinite(y_min_pos)) return res;
  res.status = Status::RankDeficient;
  if (q == 0 || p + q < static_cast<Eigen::Index>(kNumLevels)) return res;

  Eigen::MatrixXd x(p + q, 5);
  Eigen::VectorXd y(p + q), edf(p + q), model(p + q);
  for (Eigen::Index i = 0; i < p + q; ++i) {
    const bool a = i < p;
    const auto iu = static_cast<std::size_t>(a ? i : i - p);
    const double tau = a ? r.tau[iu] : r.mdev_tau[iu];
    for (std::size_t j = 0; j < kNumLevels; ++j)
      x(i, static_cast<Eigen::Index>(j)) =
          a ? avar_per_h(kAlphas[j], tau, tau0_s) : mvar_per_h(kAlphas[j], tau, tau0_s);
    y(i) = a ? r.var[iu] : r.mdev_var[iu];
    edf(i) = a ? r.edf[iu] : r.mdev_edf[iu];
    model(i) = std::max(y(i), y_min_pos);
  }
  detail::WeightedDesign design;
  Eigen::MatrixXd masked;
  detail::Qr qr;
  const detail::ReweightedNnls solved =
      detail::reweighted_nnls(x, y, edf, model, detail::Reweighting{}, design, masked, qr);
  if (solved.rank < kNumTerms) return res;
  res.iterations = solved.iterations;

  OavarCovariance cov_model;
  cov_model.prepare(r.m, r.n, tau0_s, options.threads);
  Eigen::MatrixXd sigma_a;
  cov_model.assemble(eq3_theta(solved.theta, tau0_s, r.tau.front()), sigma_a);
  const Eigen::MatrixXd sigma = row_covariance(sigma_a, r, model);
  const auto sandwich = [&](const detail::Estimator& amat, detail::TermCov& cov) {
    for (int a = 0; a < kNumTerms; ++a) {
      const Eigen::VectorXd t = sigma * amat.row(a).transpose();
      for (int b = 0; b < kNumTerms; ++b)
        cov(a, b) = amat.row(b).dot(t);
    }
  };
  std::array<TermFit, kNumTerms> terms{};
  detail::TermCov theta_cov;
  detail::Estimator a_free;
  detail::fit_terms(solved.theta, y, design, options.detection_sigmas, options.upper_confidence,
                    sandwich, masked, qr, terms, theta_cov, a_free);
  for (std::size_t j = 0; j < kNumLevels; ++j) {
    Level& l = res.levels[j];
    const TermFit& t = terms[j];
    l.h = t.theta;
    l.h_sigma = t.theta_sigma;
    l.h_free = t.theta_free;
    l.detected = t.detected;
    l.h_upper = t.upper * t.upper;
  }
  res.tau_s = r.tau;
  res.mdev_tau_s = r.mdev_tau;
  for (Eigen::Index i = 0; i < p + q; ++i)
    (i < p ? res.adev_model : res.mdev_model).push_back(std::sqrt(std::max(model(i), 0.0)));
  res.status = solved.converged ? Status::Ok : Status::NoConvergence;
  return res;
}

}  // namespace allanlot::kernels::powerlaw
