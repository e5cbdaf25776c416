// The paper's equation (3) fitted to an overlapping Allan variance curve, with uncertainties
// that account for the correlation between the estimates at neighbouring taus.
//
// Model (docs/formats.md "Units and conventions"; paper eq. (3); IEEE Std 952-1997 annex C):
//
//   avar(tau) = R^2 tau^2/2 + K^2 tau/3 + B^2 (2 ln2/pi) + N^2/tau + 3 Q^2/tau^2
//             = sum_j theta_j g_j(tau),   theta = (R^2, K^2, B^2, N^2, Q^2) >= 0,
//
// linear in the squared coefficients theta, which are the parameters of the least squares.
//
// Estimator: non-negative weighted least squares (Lawson & Hanson, "Solving Least Squares
// Problems", 1974, ch. 23, active-set NNLS) of theta on the avar estimates, with row weights
// edf_i / (2 avar_model_i^2), the inverse of var(avar_hat_i) = 2 avar_i^2 / edf_i (NIST SP1065
// sec. 5.3.3: edf * avar_hat / avar is chi-square with edf degrees of freedom). The weights use
// the model value, not the estimate (iteratively reweighted: weights from the estimate would
// favour the estimates that fell low and bias the fit low). Why NNLS on theta rather than a fit
// in log space: the model is linear in theta, so the constrained problem is convex with a
// unique solution that the active-set method finds exactly in a few steps (5 columns), a term
// at its bound is reported as exactly zero rather than as an ill-defined tiny exponent, and the
// covariance of the estimator is an exact linear propagation (below). A log-space fit would be
// non-linear and non-convex with flat directions for absent terms.
//
// Uncertainty: the overlapping estimates at neighbouring taus share most of their data and are
// strongly correlated (0.9 and more at 16 taus per decade), so the usual (X^T W X)^-1 of a
// weighted fit, which treats them as independent, understates the uncertainty several times.
// Instead the covariance of the estimates, Sigma = cov(avar_hat(m_i), avar_hat(m_j)), is
// computed from the fitted noise model (OavarCovariance below: exact for Gaussian noise, from
// the second-difference filters' cross-covariance summed over lags) and propagated through the
// estimator actually used (the sandwich form):
//
//   theta_hat_F = A y,  A = (X_F^T W X_F)^-1 X_F^T W,   cov(theta_hat_F) = A Sigma A^T,
//
// F the terms not held at zero. This is honest in the sense that it is the covariance of the
// estimator under the fitted model, including every correlation; it needs no independence
// assumption, and the test program test_kernels_fit_coverage checks on simulated data that
// |value - true| < sigma holds in 68 % of the seeds. (The dependence of W on the data adds no
// first-order term: at the fixed point the derivative of W multiplies the residual, whose mean
// is zero.) A parametric bootstrap by simulation would be as honest but costs a simulation
// and an OADEV per replica (about 0.3 s each for 5.4 M samples), a minute or more per channel
// for 200 replicas; the covariance model costs about 0.2 s of one core once per curve shape
// (m, n, tau0; 91 taus for 5.4 M samples) and is reused by every channel of that shape, and
// each fit then costs about 0.5 ms (bench_fit).
//
// Goodness of fit: chi2 = r^T Sigma^-1 r of the residual r = y - X theta_hat, and its
// expectation under the fitted model, tr(Sigma^-1 cov(r)) with cov(r) = (I - H) Sigma (I - H)^T,
// H = X_F A (this is n - p for a generalized least squares; it is larger for the weighted
// fit used here). chi2_dof = chi2 / expectation, about 1 when the model explains the curve.
#pragma once

#include "kernels/allan/stat_result.hpp"
#include "kernels/model/least_squares.hpp"
#include "kernels/model/terms.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// The five regressors g_j(tau) of eq. (3) at tau_s, in the order R, K, B, N, Q:
/// tau^2/2, tau/3, 2 ln2/pi, 1/tau, 3/tau^2.
std::array<double, kNumTerms> eq3_regressors(double tau_s);

/// Eq. (3) at tau_s for squared coefficients theta (R^2, K^2, B^2, N^2, Q^2), in u^2.
double eq3_avar(const std::array<double, kNumTerms>& theta, double tau_s);

/// Model covariance of overlapping Allan variance estimates (NIST SP1065 eq. (11)) at several
/// averaging factors, for Gaussian noise made of the five terms of eq. (3).
///
/// With d_k(m) = x_{k+2m} - 2 x_{k+m} + x_k and avar_hat(m) = sum_{k<M} d_k^2 / (2 tau^2 M),
/// M = n the number of terms, Gaussian noise gives (Isserlis' theorem)
///
///   cov(avar_hat_i, avar_hat_j) = 2 sum_l n_ij(l) c_ij(l)^2 / (4 tau_i^2 tau_j^2 M_i M_j)
///                                 + R^2 sum_l n_ij(l) c_ij(l) / (M_i M_j),
///
/// c_ij(l) = cov(d_k(m_i), d_{k+l}(m_j)), n_ij(l) the number of pairs (k, k+l) of terms, and the
/// second line the ramp's deterministic second difference R tau^2 times the noise (a ramp is
/// not random; it only scales the linear part). c is a double sum of the phase's generalized
/// autocovariance G over the nine offsets of the two filters (1, -2, 1),
/// c(l) = sum_ab w_a w_b G(tau0 (l + b - a)), valid because second differences cancel the
/// polynomials that make G generalized (Greenhall & Riley, "Uncertainty of stability variances
/// based on finite differences", Proc. 35th PTTI (2003), sec. 3.2, the function sw):
///   white rate noise N:     G(t) = -N^2 |t| / 2          (phase = Brownian motion)
///   flicker rate noise B:   G(t) = B^2 t^2 ln|t| / (2 pi)
///   rate random walk K:     G(t) = K^2 |t|^3 / 12
///   quantization Q:         G(t) = Q^2 [t = 0]           (white phase noise)
/// The constants make the variance of d equal 2 tau^2 times each term of eq. (3). These are
/// exact on sampled data for N, K and Q (the samples are interval means, as
/// simulate.hpp assumes) and the continuous-time form for flicker.
///
/// The sums run over all lags l with n(l) > 0 (up to about N). N, K and Q give c = 0 outside
/// the filters' overlap (-2 m_j < l < 2 m_i); flicker decays as l^-2 beyond it. Pieces between
/// break points of c or n of up to 16 lags, and the 2 lags next to each break point, are
/// summed exactly; the rest of each piece as the midpoint-rule integral with Euler-Maclaurin's
/// first correction, by 4-point Gauss-Legendre on panels that grow geometrically away from the
/// break points (flicker's c varies on the scale of the distance to the nearest filter knot);
/// the flicker tails likewise out to 32 times the filters' reach and by the leading asymptote
/// c ~ -tau0^2 m_i^2 m_j^2 / (pi u^2) (u the distance between the filters' centres) beyond.
/// Against the plain lag sum (test_fit.cpp) the relative error is below 1e-9 for N, 1e-6 for K
/// and 1e-4 for flicker. The result depends on theta quadratically, so prepare() stores
/// 14 basis matrices (10 products of the four random terms, 4 ramp cross terms) and
/// assemble() combines them for any theta in O(P^2).
class OavarCovariance {
public:
  /// Precomputes the basis for P = m.size() averaging factors m (strictly increasing, >= 1)
  /// with n[i] >= 1 terms each, sample interval tau0_s > 0. Cost O(P^2) lag sums of O(log m)
  /// points each (about 0.2 s for P = 91, m up to 1.35e6), the rows on `threads` OpenMP threads
  /// (every entry computed alone: the same bits for any count). Throws std::invalid_argument for
  /// broken preconditions.
  void prepare(std::span<const std::int64_t> m, std::span<const std::int64_t> n, double tau0_s,
               int threads = 1);
  /// True when prepare() was last called with exactly these arguments.
  bool matches(std::span<const std::int64_t> m, std::span<const std::int64_t> n,
               double tau0_s) const;
  /// Covariance (P x P, u^4) for squared coefficients theta, written into `out` (resized).
  void assemble(const std::array<double, kNumTerms>& theta, Eigen::MatrixXd& out) const;
  std::size_t size() const { return m_.size(); }

private:
  void set_pair(Eigen::Index i, Eigen::Index j);  // basis entries (i, j) and (j, i)

  std::vector<std::int64_t> m_, n_;
  double tau0_s_ = 0.0;
  // basis_[k] for k < 10: the products QQ, QN, QB, QK, NN, NB, NK, BB, BK, KK (scaled by
  // 2 / (4 tau_i^2 tau_j^2 M_i M_j)); k = 10..13: ramp cross terms with Q, N, B, K (scaled by
  // 1 / (M_i M_j)).
  std::array<Eigen::MatrixXd, 14> basis_;
};

/// Outcome of a fit (Eigen's ComputationInfo style; broken preconditions throw).
enum class FitStatus {
  Ok,             // fitted, and the model explains the curve within its noise
  PoorFit,        // fitted, but chi2 beyond its 99.9 % quantile: the model misses something
  NoData,         // no tau, or every avar estimate is zero
  RankDeficient,  // fewer than 5 independent regressors on the taus given (see FitResult::rank)
  NoConvergence   // the reweighting did not settle within FitOptions::max_iterations
};
std::string_view fit_status_name(FitStatus s);
/// True when the fit produced coefficients (Ok or PoorFit): they are what the data gave, and
/// a poor fit says they do not describe the whole curve.
inline bool has_terms(FitStatus s) {
  return s == FitStatus::Ok || s == FitStatus::PoorFit;
}
/// The probability below which chi2 is too large for the fitted model: a clean channel is
/// called a poor fit once in 1000. chi2 is compared with the chi-square quantile of its
/// expectation's degrees of freedom (fit.cpp goodness_of_fit, psd_fit.cpp).
inline constexpr double kPoorFitProbability = 1e-3;
/// Ok, or PoorFit when chi2 exceeds the 1 - kPoorFitProbability quantile of a chi-square with
/// `dof` degrees of freedom (dof <= 0: Ok, nothing to judge by).
FitStatus judge_fit(double chi2, double dof);

/// For the results file's fit/ `method` attribute.
inline constexpr std::string_view kFitMethod =
    "eq3 NNLS on squared coefficients, weights edf/(2 avar_model^2) reweighted; sigma: sandwich "
    "with the model covariance of the OAVAR estimates";

struct FitOptions {
  double detection_sigmas = 2.0;   // detected when theta_j > this many sigma(theta_j)
  double upper_confidence = 0.95;  // one-sided confidence of TermFit::upper, in (0.5, 1)
  // Reweighting iterations (each one NNLS solve, microseconds). The reweighting converges
  // linearly; with a near-degenerate active set the contraction per step can be slow (0.63 on
  // a simulated 600 s gyro, which needed 52 steps to reach the tolerance), so the limit is far
  // above the typical 5-20 and NoConvergence means a real failure to settle.
  int max_iterations = 500;
  double tolerance = 1e-10;  // stop when the model curve changes by less than this (relative)
  double readout_confidence = 0.683;  // two-sided CI level behind Readout::sigma
  double rank_threshold = 1e-10;      // ColPivHouseholderQR threshold on the scaled design
  // OpenMP threads of the covariance basis (OavarCovariance::prepare, a curve shape's first
  // fit); each entry is computed alone, so no result depends on it.
  int threads = 1;
};

/// A conventional read-out of the curve (IEEE Std 952-1997 annex C), with the same read-out
/// applied to the fitted model curve for comparison.
struct Readout {
  bool valid = false;  // the fit detects the term this read-out estimates (see FitResult)
  double value = 0.0;  // in the docs/formats.md unit of its term
  double sigma = 0.0;  // half the chi-square interval (FitOptions::readout_confidence) there
  double tau_s = 0.0;  // where the curve was read
  double model = 0.0;  // the same read-out applied to the fitted eq. (3) curve
};

struct FitResult {
  FitStatus status = FitStatus::NoData;
  int rank = 0;        // numerical rank of the weighted, column-scaled design (<= 5)
  int iterations = 0;  // reweighting iterations used
  std::array<TermFit, kNumTerms> terms{};  // indexed by static_cast<int>(Term)
  // Covariance of the fitted theta (sandwich, u^4 s^..): rows and columns of terms held at
  // zero are zero.
  Eigen::Matrix<double, kNumTerms, kNumTerms> theta_cov =
      Eigen::Matrix<double, kNumTerms, kNumTerms>::Zero();
  double residual_norm = 0.0;      // || diag(sqrt(w)) (avar - model) ||_2 with the final weights
  double chi2 = 0.0;               // r^T Sigma^-1 r
  double chi2_expected = 0.0;      // its expectation under the fitted model
  double chi2_dof = 0.0;           // chi2 / chi2_expected (0 when the expectation is 0)
  int dof = 0;                     // number of taus - number of free terms
  std::vector<double> avar_model;  // eq. (3) at the input taus (u^2)
  std::vector<double> adev_model;  // its square root (docs/formats.md fit/adev_model)
  // Conventional read-outs of the measured curve (IEEE Std 952-1997 annex C), for comparison
  // with datasheets. Each is a lower envelope of eq. (3), so each reads high by whatever else
  // contributes at its tau; Readout::model applies the same read-out to the fitted curve (at
  // the input taus), so model / fitted value - 1 is the bias the fit predicts. A read-out is
  // `valid` only when the fit detects the term whose branch it reads: a fixed-slope read-out
  // of a branch the curve does not have is meaningless (the field's NaN and nonsense reports).
  //  - n_1s: N = sigma(1 s) sqrt(1 s), the curve at tau = 1 s (log-log interpolated between
  //    the neighbouring taus, edf interpolated linearly); avar(1 s) = N^2 + (R, K, B, Q terms
  //    at 1 s), so it exceeds N when flicker or quantization still count at 1 s. value 0 when
  //    1 s is outside the taus.
  //  - bias_instability: B = min sigma / sqrt(2 ln2/pi) (0.664), at the tau of the minimum;
  //    at the minimum of N^2/tau + c B^2 + K^2 tau/3 (tau = sqrt(3) N/K) the curve exceeds the
  //    floor by 2 N K / sqrt(3), so the read-out is high whenever N or K still contribute
  //    there, and the minimum of a noisy curve is biased low (the lowest of many correlated
  //    estimates).
  //  - k_3s: the lowest line of slope +1/2 that touches the curve, read at tau = 3 s, where
  //    sigma_line(3 s) = K: K = min_i sigma(tau_i) sqrt(3 / tau_i), tau_s the touching tau.
  //    avar >= K^2 tau / 3 everywhere, so this is an upper bound of K that is tight only on a
  //    true +1/2 branch (reading the curve itself at 3 s, as often done, is only right when
  //    the +1/2 branch already dominates at 3 s).
  // sigma is the half-width of the chi-square interval of the deviation at the read-out tau
  // (kernels::chi2_interval with the input edf), scaled like the value.
  Readout n_1s, bias_instability, k_3s;

  const TermFit& operator[](Term t) const { return terms[static_cast<std::size_t>(t)]; }
};

/// One overlapping Allan curve to fit (views into caller-owned arrays of equal length P).
struct FitInput {
  std::span<const double> tau_s;    // strictly increasing, each a multiple m of tau0_s
  std::span<const double> values;   // avar (u^2) or, when is_deviation, dev (u)
  bool is_deviation = false;        // values are deviations; they are squared
  std::span<const std::int64_t> n;  // terms in each estimate (1 <= n <= n_samples + 1 - 2 m)
  std::span<const double> edf;      // equivalent degrees of freedom, finite and > 0
  double tau0_s = 0.0;              // sample interval 1 / rate, > 0
  std::int64_t n_samples = 0;       // rate samples of the channel (N + 1 phase points)
};

/// The rows `rows` (increasing indices) of `r` whose averaging factor is at least first_m, with
/// what Eq3Fit::fit reads of them (m, tau_s, dev, n, edf): the part of a curve to fit, e.g.
/// without the shortest taus that a sensor's filter biases.
StatResult fit_subset(const StatResult& r, std::span<const std::size_t> rows,
                      std::int64_t first_m = 1);
/// Every row of `r` from averaging factor first_m on.
StatResult fit_subset(const StatResult& r, std::int64_t first_m);

/// The eq. (3) fit as a reusable plan (Eigen's decomposition style): the constructor reserves
/// the workspaces for up to `max_taus` taus; fit() rebuilds the covariance basis only when the
/// curve's shape (m, n, tau0) differs from the previous call's, so the channels of a lot, which
/// share their length and tau grid, pay for it once. Not safe to call from two threads at once
/// (use one object per thread); OpenMP only in that rebuild (FitOptions::threads), which gives
/// the same bits for any thread count. Deterministic.
class Eq3Fit {
public:
  explicit Eq3Fit(std::size_t max_taus = 0, FitOptions options = {});

  /// Fits `in`. Throws std::invalid_argument for broken preconditions: unequal lengths,
  /// tau0_s or n_samples not positive, a tau that is not finite, not > 0, not increasing or not
  /// within 1e-9 relative of a multiple of tau0_s, a value that is negative or not finite, an
  /// edf that is not finite and > 0, an n out of its range. Numerical outcomes are in the
  /// status. P = 0 gives NoData.
  FitResult fit(const FitInput& in);

  /// Fits an overlapping Allan deviation result with its edf filled (kernels::add_confidence):
  /// tau_s, dev, n and edf of `oadev`, for a channel of `n_samples` rate samples at tau0_s.
  FitResult fit(const StatResult& oadev, double tau0_s, std::int64_t n_samples);

  /// The model covariance of the avar estimates (P x P) at the last fit's theta.
  const Eigen::MatrixXd& covariance() const { return sigma_; }
  const FitOptions& options() const { return options_; }
  /// FitOptions::threads for the next fits.
  void set_threads(int threads) { options_.threads = threads; }

private:
  // The steps of fit(FitInput).
  void check_input(const FitInput& in);  // fills m_
  double load(const FitInput& in);       // fills x_, y_, edf_; the smallest positive y
  void goodness_of_fit(const Eigen::VectorXd& r, FitResult& res) const;
  void readouts(const FitInput& in, const std::array<double, kNumTerms>& th,
                const Eigen::VectorXd& model, FitResult& res) const;

  FitOptions options_;
  OavarCovariance cov_model_;
  std::vector<std::int64_t> m_;
  Eigen::MatrixXd x_;              // P x 5 design
  Eigen::VectorXd y_;              // avar
  Eigen::VectorXd edf_;            // edf
  Eigen::MatrixXd sigma_;          // model covariance of y
  detail::WeightedDesign design_;  // weighted, column-scaled design and weighted avar
  Eigen::MatrixXd masked_;         // design_.xs with the columns of a subproblem
  detail::Estimator amat_;         // estimator matrix A on the free terms (sandwich)
  detail::Qr qr_;
};

}  // namespace allanlot::kernels
