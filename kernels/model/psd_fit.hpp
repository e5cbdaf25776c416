// The paper's five-term noise model fitted to the Welch PSD alone (the `psd_fit/` group of the
// results layout), to compare term by term with the Allan-domain fit (kernels/model/fit.hpp).
//
// PSD forms of the terms (paper, below eq. (3); two-sided S2, and the one-sided S1 = 2 S2 of
// docs/formats.md "Units and conventions"):
//   R (ramp):              S2 = R^2 / (2 pi f)^3
//   K (rate random walk):  S2 = K^2 / (2 pi f)^2     S1 = K^2 / (2 pi^2 f^2)
//   B (flicker):           S2 = B^2 / (2 pi f)       S1 = B^2 / (pi f)
//   N (white):             S2 = N^2                  S1 = 2 N^2
//   Q (quantization):      S2 = (2 pi f)^2 Q^2 tau0  S1 = 8 Q^2 sin^2(pi f tau0) / tau0 (sampled)
// The fit does not use these asymptotic forms bin by bin. It uses what the Welch estimator
// (kernels/spectral/psd.hpp) returns on average for each term: for a stationary term with rate
// autocovariance r(d) (lag d samples),
//
//   E[P_k] = c_k / (rate_hz sum_t w_t^2) sum_{|d| < L} r(d) a_w(d) cos(2 pi k d / L),
//
// a_w(d) = sum_t w_t w_{t+d} the Hann window's autocorrelation, c_k the one-sided factor. This
// is the model spectrum convolved with the window's spectral window, aliasing included, so the
// fit is unbiased at every bin k >= 2, also where the 1/f and 1/f^2 terms curve within the
// window's main lobe (a bias of 10-30 % at k = 2..4 if the forms above were used directly).
// r(d) comes from the phase's generalized autocovariance G of each term, the same functions
// as the Allan-domain covariance model (kernels/model/fit.hpp; Greenhall & Riley, PTTI 2003):
// r(d) = [2 G(d tau0) - G((d+1) tau0) - G((d-1) tau0)] / tau0^2 (rate samples are interval
// means, first differences of the phase). G of random walk and flicker is defined only up to
// an even polynomial of degree 2; in r that is a constant, which the sum removes exactly
// because sum_d a_w(d) cos(2 pi k d / L) = |W_k|^2 = 0 for the periodic Hann at k >= 2 (the
// same reason the per-segment mean removal does not matter there). The ramp is deterministic:
// each segment holds R tau0 t (t = 0 .. L-1) plus a constant, so
// E[P_k] = c_k R^2 tau0^2 |sum_t t w_t e^{-2 pi i k t / L}|^2 / (rate_hz sum_t w_t^2), also
// exact. Flicker uses the continuous-time 1/f form (a real sensor's), which differs from a
// discrete-time (Kasdin) flicker only near Nyquist, where white noise dominates.
//
// Estimator: the log-binned PSD (kernels::log_bin, bins k >= first_bin) is linear in the
// squared coefficients theta = (R^2, K^2, B^2, N^2, Q^2), each binned value being the mean of
// E[P_k] over its Welch bins; non-negative least squares with weights edf_b / (2 model_b^2)
// (a Welch bin average with edf nu is model * chi2_nu / nu), iteratively reweighted with the
// model (as the Allan fit, and for the same reason: weights from the estimate favour bins that
// fell low). Unlike the Allan curve, the binned PSD values are nearly independent: two log bins
// share only the Hann correlation of their adjacent Welch bins, r_1 = 4/9 and r_2 = 1/36
// (Percival & Walden 1993, sec. 6.6), which the covariance Sigma below includes. The
// uncertainty is the sandwich A Sigma A^T of the weighted estimator (A as in fit.hpp), so it
// stays honest with that residual correlation; chi2_dof = r^T Sigma^-1 r / (P - free terms).
//
// What the PSD sees: its lowest bin is 2 rate_hz / L (L the Welch segment length), so with 16
// segments over 90 minutes at 1 kHz it starts at 0.015 Hz. Terms that show only below that
// (random walk and ramp at the paper's levels, flicker of a good gyro) come out undetected
// with wide bounds, while the Allan curve, which reaches tau = record / 4, does detect them.
// That is the honest difference between the two views, not a disagreement.
#pragma once

#include "kernels/model/fit.hpp"
#include "kernels/spectral/psd.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// For the results file's psd_fit/ `method` attribute.
inline constexpr std::string_view kPsdFitMethod =
    "eq3 terms fitted to the log-binned Welch PSD (expected Welch value of each term: Hann "
    "window and aliasing exact), NNLS on squared coefficients, weights edf/(2 psd_model^2) "
    "reweighted; sigma: sandwich with the bins' chi-square covariance";

/// Expected Welch value, per unit squared coefficient, of each eq. (3) term at the Welch bins
/// k = 0 .. L/2 of segment length L (see the file comment): out[term][k] in u^2/Hz per
/// (u^2 s^p), indexed by static_cast<int>(Term). Valid for k >= 2 (bins 0 and 1 also depend on
/// the per-segment mean removal; their entries are NaN). L even, >= 16; rate_hz > 0
/// (std::invalid_argument otherwise).
std::array<std::vector<double>, kNumTerms> welch_term_psd(std::int64_t segment_length,
                                                          double rate_hz, int threads = 1);

/// welch_term_psd for the last (segment_length, rate_hz) asked: the channels of a lot share
/// both, so they pay for the regressors (two FFTs of the segment length and a cosine per
/// sample, about 120 ms at L = 2^18) once. Same values as welch_term_psd. One object per
/// thread (Eq3Fit's pattern).
class WelchTermCache {
public:
  const std::array<std::vector<double>, kNumTerms>& get(std::int64_t segment_length, double rate_hz,
                                                        int threads = 1);

private:
  std::int64_t segment_length_ = 0;
  double rate_hz_ = 0.0;
  std::array<std::vector<double>, kNumTerms> terms_;
};

struct PsdFitOptions {
  std::int64_t first_bin = 2;     // lowest Welch bin used (>= 2, see welch_term_psd)
  int bins_per_decade = 10;       // log binning of the PSD (kernels::log_bin)
  int n_linear = 4;               // Welch bins kept unbinned at the low end (kernels::log_bin)
  double detection_sigmas = 2.0;  // as FitOptions
  double upper_confidence = 0.95;
  int max_iterations = 50;
  double tolerance = 1e-10;
  double rank_threshold = 1e-10;
  int threads = 1;  // OpenMP threads of welch_term_psd (the regressors; same bits for any count)
};

/// The PSD-domain fit.
struct PsdFitResult {
  FitStatus status = FitStatus::NoData;
  int rank = 0;
  int iterations = 0;
  std::array<TermFit, kNumTerms> terms{};  // as FitResult::terms
  Eigen::Matrix<double, kNumTerms, kNumTerms> theta_cov =
      Eigen::Matrix<double, kNumTerms, kNumTerms>::Zero();
  double chi2 = 0.0;      // r^T Sigma^-1 r
  double chi2_dof = 0.0;  // chi2 / (P - free terms)
  int dof = 0;
  std::vector<double> f_hz;       // the binned frequencies fitted
  std::vector<double> psd;        // the binned PSD there (one-sided, u^2/Hz)
  std::vector<double> edf;        // its chi-square dof
  std::vector<double> psd_model;  // the fitted model's expected Welch value there

  const TermFit& operator[](Term t) const { return terms[static_cast<std::size_t>(t)]; }
};

/// Fits eq. (3) to a Welch PSD from kernels::welch / welch_psd. Broken preconditions
/// (psd not from welch, options out of range) throw std::invalid_argument; too few bins gives
/// status NoData, a design that cannot separate the five terms RankDeficient. Deterministic,
/// no threads. `terms` (optional) keeps the regressors from channel to channel.
PsdFitResult psd_fit(const PsdResult& psd, const PsdFitOptions& options = {},
                     WelchTermCache* terms = nullptr);

/// Term-by-term comparison of two fits of the same channel (the Allan fit and the PSD fit).
struct FitAgreement {
  // z_j = (theta_free_a - theta_free_b) / sqrt(sigma_a^2 + sigma_b^2) on the squared
  // coefficients (0 when both sigmas are 0). theta_free rather than theta, so that a term held
  // at zero by one fit and slightly positive in the other compares by its unconstrained value.
  std::array<double, kNumTerms> z{};
  double max_abs_z = 0.0;
  int worst_term = -1;  // index of max |z| (-1 when no term has a sigma)
  bool agree = true;    // max_abs_z <= threshold
};

/// Compares two sets of fitted terms. Both fits use the same data, so their errors are
/// positively correlated and var(a - b) < sigma_a^2 + sigma_b^2: treating them as independent
/// makes |z| smaller, i.e. the test is conservative (it flags fewer disagreements than a test
/// with the exact covariance). threshold 3: a 0.3 % two-sided false alarm per term for
/// independent estimates, about 1.3 % over five terms.
FitAgreement compare_fits(const std::array<TermFit, kNumTerms>& a,
                          const std::array<TermFit, kNumTerms>& b, double threshold = 3.0);

}  // namespace allanlot::kernels
