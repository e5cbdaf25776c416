#include "kernels/model/fit.hpp"

#include "kernels/model/least_squares.hpp"
#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

// Determinism: every product below is a matrix-vector product, a triangular solve with a
// vector right-hand side or a small (<= 5 column) factorization, none of which Eigen hands to
// OpenMP; the P x P factorization is LDLT (unblocked rank-1 updates). So the result is the
// same for any OMP_NUM_THREADS (checked in test_fit.cpp).

namespace allanlot::kernels {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kFlickerFloor = 2.0 * std::numbers::ln2 / kPi;  // eq. (3): B^2 2 ln2 / pi
constexpr int kR = static_cast<int>(Term::R);
constexpr int kK = static_cast<int>(Term::K);
constexpr int kB = static_cast<int>(Term::B);
constexpr int kN = static_cast<int>(Term::N);
constexpr int kQ = static_cast<int>(Term::Q);

// A double in a precondition message: std::to_string prints "%f", which shows 1e-300 as
// 0.000000 and 1e300 as 301 digits; the message must show the value that was wrong.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument(what);
}

double half_interval(double dev, double edf, double confidence) {
  if (!(dev > 0.0)) return 0.0;
  const Interval ci = chi2_interval(dev, edf, confidence);
  return 0.5 * (ci.hi - ci.lo);
}

}  // namespace

std::array<double, kNumTerms> eq3_regressors(double tau_s) {
  std::array<double, kNumTerms> g{};
  g[kR] = 0.5 * tau_s * tau_s;
  g[kK] = tau_s / 3.0;
  g[kB] = kFlickerFloor;
  g[kN] = 1.0 / tau_s;
  g[kQ] = 3.0 / (tau_s * tau_s);
  return g;
}

double eq3_avar(const std::array<double, kNumTerms>& theta, double tau_s) {
  const auto g = eq3_regressors(tau_s);
  double s = 0.0;
  for (std::size_t j = 0; j < g.size(); ++j)
    s += theta[j] * g[j];
  return s;
}

std::string_view fit_status_name(FitStatus s) {
  switch (s) {
  case FitStatus::Ok:
    return "ok";
  case FitStatus::PoorFit:
    return "poor fit";
  case FitStatus::NoData:
    return "no data";
  case FitStatus::RankDeficient:
    return "rank deficient";
  case FitStatus::NoConvergence:
    return "no convergence";
  }
  return "unknown";
}

FitStatus judge_fit(double chi2, double dof) {
  if (!(dof > 0.0) || !std::isfinite(chi2)) return FitStatus::Ok;
  return chi2 > chi2_quantile(1.0 - kPoorFitProbability, dof) ? FitStatus::PoorFit : FitStatus::Ok;
}

Eq3Fit::Eq3Fit(std::size_t max_taus, FitOptions options) : options_(options) {
  if (!(options_.upper_confidence > 0.5 && options_.upper_confidence < 1.0))
    fail("Eq3Fit: options.upper_confidence must be in (0.5, 1), got " +
         std::to_string(options_.upper_confidence));
  if (!(options_.readout_confidence > 0.0 && options_.readout_confidence < 1.0))
    fail("Eq3Fit: options.readout_confidence must be in (0, 1), got " +
         std::to_string(options_.readout_confidence));
  if (options_.max_iterations < 1)
    fail("Eq3Fit: options.max_iterations must be >= 1, got " +
         std::to_string(options_.max_iterations));
  const auto p = static_cast<Eigen::Index>(max_taus);
  m_.reserve(max_taus);
  x_.resize(p, kNumTerms);
  y_.resize(p);
  edf_.resize(p);
  design_.sw.resize(p);
  sigma_.resize(p, p);
  design_.xs.resize(p, kNumTerms);
  masked_.resize(p, kNumTerms);
  design_.bs.resize(p);
  amat_.resize(kNumTerms, p);
  qr_ = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(p, kNumTerms);
}

StatResult fit_subset(const StatResult& r, std::span<const std::size_t> rows,
                      std::int64_t first_m) {
  StatResult sub;
  for (const std::size_t i : rows) {
    if (r.m[i] < first_m) continue;
    sub.m.push_back(r.m[i]);
    sub.tau_s.push_back(r.tau_s[i]);
    sub.dev.push_back(r.dev[i]);
    sub.n.push_back(r.n[i]);
    sub.edf.push_back(r.edf[i]);
  }
  return sub;
}

StatResult fit_subset(const StatResult& r, std::int64_t first_m) {
  std::vector<std::size_t> rows(r.size());
  std::iota(rows.begin(), rows.end(), std::size_t{0});
  return fit_subset(r, rows, first_m);
}

FitResult Eq3Fit::fit(const StatResult& oadev, double tau0_s, std::int64_t n_samples) {
  if (oadev.edf.size() != oadev.size())
    fail("Eq3Fit::fit: the oadev result has no edf (" + std::to_string(oadev.edf.size()) + " for " +
         std::to_string(oadev.size()) + " rows); run add_confidence first");
  FitInput in;
  in.tau_s = oadev.tau_s;
  in.values = oadev.dev;
  in.is_deviation = true;
  in.n = oadev.n;
  in.edf = oadev.edf;
  in.tau0_s = tau0_s;
  in.n_samples = n_samples;
  return fit(in);
}

void Eq3Fit::check_input(const FitInput& in) {
  const std::size_t pu = in.tau_s.size();
  if (in.values.size() != pu || in.n.size() != pu || in.edf.size() != pu)
    fail("Eq3Fit::fit: tau_s, values, n and edf differ in length (" + std::to_string(pu) + ", " +
         std::to_string(in.values.size()) + ", " + std::to_string(in.n.size()) + ", " +
         std::to_string(in.edf.size()) + ")");
  if (!(in.tau0_s > 0.0) || !std::isfinite(in.tau0_s))
    fail("Eq3Fit::fit: tau0_s must be finite and > 0, got " + num(in.tau0_s));
  if (in.n_samples < 1)
    fail("Eq3Fit::fit: n_samples must be >= 1, got " + std::to_string(in.n_samples));
  m_.resize(pu);
  for (std::size_t i = 0; i < pu; ++i) {
    const double tau = in.tau_s[i];
    if (!(tau > 0.0) || !std::isfinite(tau))
      fail("Eq3Fit::fit: tau_s must be finite and > 0, got " + num(tau));
    if (i > 0 && !(tau > in.tau_s[i - 1]))
      fail("Eq3Fit::fit: tau_s must be strictly increasing, got " + num(in.tau_s[i - 1]) +
           " then " + num(tau));
    const double mf = std::round(tau / in.tau0_s);
    if (mf < 1.0 || std::abs(tau - mf * in.tau0_s) > 1e-9 * tau)
      fail("Eq3Fit::fit: tau_s " + num(tau) + " is not a multiple of tau0_s " + num(in.tau0_s));
    m_[i] = static_cast<std::int64_t>(mf);
    const double v = in.values[i];
    if (!(v >= 0.0) || !std::isfinite(v))
      fail("Eq3Fit::fit: values must be finite and >= 0, got " + num(v) + " at tau " + num(tau));
    if (!(in.edf[i] > 0.0) || !std::isfinite(in.edf[i]))
      fail("Eq3Fit::fit: edf must be finite and > 0, got " + num(in.edf[i]) + " at tau " +
           num(tau));
    const std::int64_t n_max = in.n_samples + 1 - 2 * m_[i];
    if (in.n[i] < 1 || in.n[i] > n_max)
      fail("Eq3Fit::fit: n must be in [1, " + std::to_string(n_max) + "] at m " +
           std::to_string(m_[i]) + ", got " + std::to_string(in.n[i]));
  }
}

double Eq3Fit::load(const FitInput& in) {
  const auto p = static_cast<Eigen::Index>(in.tau_s.size());
  y_.resize(p);
  edf_.resize(p);
  x_.resize(p, kNumTerms);
  design_.sw.resize(p);
  double y_min_pos = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < p; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double v = in.values[iu];
    y_(i) = in.is_deviation ? v * v : v;
    edf_(i) = in.edf[iu];
    if (y_(i) > 0.0) y_min_pos = std::min(y_min_pos, y_(i));
    const auto g = eq3_regressors(in.tau_s[iu]);
    for (int j = 0; j < kNumTerms; ++j)
      x_(i, j) = g[static_cast<std::size_t>(j)];
  }
  return y_min_pos;
}

FitResult Eq3Fit::fit(const FitInput& in) {
  check_input(in);
  FitResult res;
  const std::size_t pu = in.tau_s.size();
  const auto p = static_cast<Eigen::Index>(pu);
  const double y_min_pos = load(in);
  if (p == 0 || !std::isfinite(y_min_pos)) {
    res.status = FitStatus::NoData;
    return res;
  }

  // Iteratively reweighted NNLS on the weighted, column-scaled design (least_squares.hpp),
  // from the estimates as the first model (zeros raised to the smallest positive one).
  Eigen::VectorXd model(p);
  for (Eigen::Index i = 0; i < p; ++i)
    model(i) = std::max(y_(i), y_min_pos);
  const detail::Reweighting reweighting{options_.rank_threshold, options_.max_iterations,
                                        options_.tolerance, 0.0};
  const detail::ReweightedNnls solved =
      detail::reweighted_nnls(x_, y_, edf_, model, reweighting, design_, masked_, qr_);
  if (!detail::take_solution(res, solved, FitStatus::RankDeficient)) return res;
  const detail::Theta& theta = solved.theta;

  std::array<double, kNumTerms> th{};
  for (int j = 0; j < kNumTerms; ++j)
    th[static_cast<std::size_t>(j)] = theta(j);
  if (!cov_model_.matches(m_, in.n, in.tau0_s))
    cov_model_.prepare(m_, in.n, in.tau0_s, options_.threads);
  cov_model_.assemble(th, sigma_);

  // Sandwich covariance of the weighted estimator, cov = A Sigma A^T with the correlated model
  // covariance Sigma of the estimates, row by row (serial matrix-vector products).
  const auto sandwich = [&](const detail::Estimator& amat, detail::TermCov& cov) {
    for (int a = 0; a < kNumTerms; ++a) {
      const Eigen::VectorXd t = sigma_ * amat.row(a).transpose();
      for (int b = 0; b < kNumTerms; ++b)
        cov(a, b) = amat.row(b).dot(t);
    }
  };
  const int n_free =
      detail::fit_terms(theta, y_, design_, options_.detection_sigmas, options_.upper_confidence,
                        sandwich, masked_, qr_, res.terms, res.theta_cov, amat_);

  // Residuals and goodness of fit with the correlated covariance.
  const Eigen::VectorXd r = y_ - model;
  res.residual_norm = design_.sw.cwiseProduct(r).norm();
  res.dof = static_cast<int>(p) - n_free;
  goodness_of_fit(r, res);

  res.avar_model.resize(pu);
  res.adev_model.resize(pu);
  for (std::size_t i = 0; i < pu; ++i) {
    res.avar_model[i] = model(static_cast<Eigen::Index>(i));
    res.adev_model[i] = std::sqrt(res.avar_model[i]);
  }
  readouts(in, th, model, res);
  // chi2's expectation under the model is its effective degrees of freedom (the residual is
  // correlated and weighted, see goodness_of_fit).
  res.status = solved.converged ? judge_fit(res.chi2, res.chi2_expected) : FitStatus::NoConvergence;
  return res;
}

void Eq3Fit::goodness_of_fit(const Eigen::VectorXd& r, FitResult& res) const {
  const Eigen::Index p = r.size();
  // tr(H) = tr(A X) and the expectation of r^T Sigma^-1 r (see the header):
  // P - 2 tr(A X) + tr((X^T Sigma^-1 X) cov), A the estimator on the free columns.
  double tr_h = 0.0;
  for (int j = 0; j < kNumTerms; ++j)
    tr_h += amat_.row(j).dot(x_.col(j));
  Eigen::LDLT<Eigen::MatrixXd> ldlt(sigma_);
  const bool pd = ldlt.info() == Eigen::Success && ldlt.isPositive() &&
                  ldlt.vectorD().minCoeff() > 1e-14 * ldlt.vectorD().maxCoeff();
  Eigen::MatrixXd sinv_x(p, kNumTerms);
  Eigen::VectorXd sinv_r(p);
  if (pd) {
    sinv_r = ldlt.solve(r);
    for (int j = 0; j < kNumTerms; ++j)
      sinv_x.col(j) = ldlt.solve(x_.col(j).eval());
  } else {
    // Numerically semi-definite model (e.g. a single term whose estimates at the longest taus
    // are almost perfectly correlated): pseudo-inverse with eigenvalues below 1e-14 of the
    // largest dropped.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sigma_);
    const Eigen::VectorXd& ev = es.eigenvalues();
    const double floor = 1e-14 * ev.maxCoeff();
    Eigen::VectorXd inv(p);
    for (Eigen::Index i = 0; i < p; ++i)
      inv(i) = ev(i) > floor ? 1.0 / ev(i) : 0.0;
    const Eigen::MatrixXd& v = es.eigenvectors();
    const auto apply = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
      const Eigen::VectorXd c = v.transpose() * b;
      return v * inv.cwiseProduct(c);
    };
    sinv_r = apply(r);
    for (int j = 0; j < kNumTerms; ++j)
      sinv_x.col(j) = apply(x_.col(j));
  }
  res.chi2 = r.dot(sinv_r);
  double tr_hsh = 0.0;
  for (int a = 0; a < kNumTerms; ++a)
    for (int b = 0; b < kNumTerms; ++b)
      tr_hsh += x_.col(a).dot(sinv_x.col(b)) * res.theta_cov(b, a);
  res.chi2_expected = static_cast<double>(p) - 2.0 * tr_h + tr_hsh;
  res.chi2_dof = res.chi2_expected > 0.0 ? res.chi2 / res.chi2_expected : 0.0;
}

void Eq3Fit::readouts(const FitInput& in, const std::array<double, kNumTerms>& th,
                      const Eigen::VectorXd& model, FitResult& res) const {
  const std::size_t pu = in.tau_s.size();
  // Conventional read-outs (see FitResult).
  const double conf = options_.readout_confidence;
  const auto dev_at = [&](std::size_t i) { return std::sqrt(y_(static_cast<Eigen::Index>(i))); };
  {
    Readout& ro = res.n_1s;
    ro.tau_s = 1.0;
    ro.model = std::sqrt(eq3_avar(th, 1.0));
    if (in.tau_s.front() <= 1.0 && in.tau_s.back() >= 1.0) {
      std::size_t k = 0;
      while (k + 1 < pu && in.tau_s[k + 1] <= 1.0)
        ++k;
      double avar1 = y_(static_cast<Eigen::Index>(k));
      double edf1 = edf_(static_cast<Eigen::Index>(k));
      if (in.tau_s[k] < 1.0) {
        const auto k1 = static_cast<Eigen::Index>(k + 1);
        const auto k0 = static_cast<Eigen::Index>(k);
        const double w = std::log(1.0 / in.tau_s[k]) / std::log(in.tau_s[k + 1] / in.tau_s[k]);
        avar1 = (y_(k0) > 0.0 && y_(k1) > 0.0)
                    ? std::exp((1.0 - w) * std::log(y_(k0)) + w * std::log(y_(k1)))
                    : (1.0 - w) * y_(k0) + w * y_(k1);
        edf1 = (1.0 - w) * edf_(k0) + w * edf_(k1);
      }
      ro.valid = res.terms[kN].detected;
      ro.value = std::sqrt(avar1);
      ro.sigma = half_interval(ro.value, edf1, conf);
    }
  }
  std::size_t i_min = 0, i_k = 0;
  double model_min = std::numeric_limits<double>::infinity();
  double model_k = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pu; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    if (y_(ii) < y_(static_cast<Eigen::Index>(i_min))) i_min = i;
    if (y_(ii) / in.tau_s[i] < y_(static_cast<Eigen::Index>(i_k)) / in.tau_s[i_k]) i_k = i;
    model_min = std::min(model_min, model(ii));
    model_k = std::min(model_k, model(ii) / in.tau_s[i]);
  }
  {
    Readout& ro = res.bias_instability;
    const double scale = 1.0 / std::sqrt(kFlickerFloor);
    ro.tau_s = in.tau_s[i_min];
    ro.value = dev_at(i_min) * scale;
    ro.sigma = half_interval(dev_at(i_min), edf_(static_cast<Eigen::Index>(i_min)), conf) * scale;
    ro.model = std::sqrt(model_min) * scale;
    ro.valid = res.terms[kB].detected;
  }
  {
    Readout& ro = res.k_3s;
    const double scale = std::sqrt(3.0 / in.tau_s[i_k]);
    ro.tau_s = in.tau_s[i_k];
    ro.value = dev_at(i_k) * scale;
    ro.sigma = half_interval(dev_at(i_k), edf_(static_cast<Eigen::Index>(i_k)), conf) * scale;
    ro.model = std::sqrt(3.0 * model_k);
    ro.valid = res.terms[kK].detected;
  }
}

}  // namespace allanlot::kernels
