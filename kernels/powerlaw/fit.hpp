// The power-law noise model of a clock (NIST SP1065 sec. 5.1, p. 20): the fractional frequency's
// one-sided PSD S_y(f) = sum_alpha h_alpha f^alpha over white PM (alpha 2), flicker PM (1), white
// FM (0), flicker FM (-1) and random-walk FM (-2), fitted to the overlapping Allan variance and
// the modified Allan variance of the channel at once:
//
//   avar(tau) = sum_alpha h_alpha a_alpha(tau),   mvar(tau) = sum_alpha h_alpha b_alpha(tau),
//
// a and b from kernels/powerlaw/theory.hpp. AVAR alone cannot tell white from flicker PM (both
// go as tau^-2 up to a logarithm); MVAR can (tau^-3 against tau^-2, SP1065 sec. 5.2.5), so its
// rows join the fit.
//
// Estimator: the one active-set NNLS of kernels/model/least_squares.hpp on the levels h >= 0,
// iteratively reweighted with the weights edf / (2 model^2) (the inverse variance of a
// chi-square estimate under the model, SP1065 sec. 5.3.3), as the eq. (3) fit
// (kernels/model/fit.hpp) does.
//
// Uncertainty: the sandwich A Sigma A^T of the estimator actually used, with Sigma the
// covariance of the estimates under the fitted model. Its AVAR block is OavarCovariance
// (kernels/model/fit.hpp), exact for Gaussian white PM, white FM, flicker FM and random-walk FM,
// which are eq. (3)'s Q, N, B and K (Q^2 = h_2 f_h / (4 pi^2), N^2 = h_0 / 2, B^2 = pi h_-1,
// K^2 = 2 pi^2 h_-2); flicker PM, which eq. (3) lacks, enters it as the white PM of the same
// Allan variance at the shortest tau. The MVAR rows take the variance 2 mvar^2 / edf of their
// chi-square and the AVAR rows' correlation at the same m, and are taken as fully correlated
// with the AVAR row of their m (MVAR equals AVAR at m = 1 and follows it closely beyond): the
// MVAR rows then add no independent information that they do not have, which keeps the sigmas
// from being understated. A level is detected when h > detection_sigmas * sigma (one-sided Wald
// test, as eq. (3)'s terms); otherwise its upper bound is the number to read.
#pragma once

#include "kernels/allan/stat_result.hpp"
#include "kernels/powerlaw/names.hpp"

#include <array>
#include <string_view>
#include <vector>

namespace allanlot::kernels::powerlaw {

/// One fitted level.
struct Level {
  int alpha = 0;
  double h = 0.0;         // h_alpha >= 0, in Hz^(-1-alpha) (S_y in 1/Hz)
  double h_sigma = 0.0;   // 1-sigma of h (sandwich); for a level held at zero, of h_free
  double h_free = 0.0;    // h with this level allowed below zero (the others as fitted)
  double h_upper = 0.0;   // one-sided upper bound at PowerLawOptions::upper_confidence
  bool detected = false;  // h > detection_sigmas * h_sigma
};

enum class Status {
  Ok,             // fitted
  NoData,         // no OADEV row with a positive deviation and an edf
  RankDeficient,  // the rows do not tell the five levels apart (no MDEV row, too few taus)
  NoConvergence   // the reweighting did not settle
};
std::string_view status_name(Status s);

struct Options {
  double detection_sigmas = 2.0;   // as kernels::FitOptions
  double upper_confidence = 0.95;  // one-sided confidence of Level::h_upper, in (0.5, 1)
  int threads = 1;                 // OavarCovariance::prepare (the same bits for any count)
};

struct Result {
  Status status = Status::NoData;
  std::array<Level, kNumLevels> levels{};  // in the order of kAlphas
  int iterations = 0;
  std::vector<double> tau_s;       // the OADEV rows fitted
  std::vector<double> adev_model;  // sqrt of the fitted AVAR there
  std::vector<double> mdev_tau_s;  // the MDEV rows fitted (a subset of tau_s)
  std::vector<double> mdev_model;  // sqrt of the fitted MVAR there
  const Level& at(int alpha) const { return levels[level_index(alpha)]; }
};

/// Fits the five levels to `oadev` and, when given, `mdev` (both with their edf filled,
/// kernels::add_confidence) of a channel of fractional frequency sampled at tau0_s. Rows with a
/// deviation that is not finite or an edf that is not finite and > 0 are left out; MDEV rows
/// are used at the averaging factors OADEV has. Without MDEV rows (or with fewer than five rows
/// in all) the status is RankDeficient: AVAR alone cannot tell flicker from white PM.
/// Throws std::invalid_argument when tau0_s is not finite and > 0.
Result fit(const StatResult& oadev, const StatResult* mdev, double tau0_s,
           const Options& options = {});

/// AVAR and MVAR of the model with levels h (in the order of kAlphas) at tau_s.
double model_avar(const std::array<double, kNumLevels>& h, double tau_s, double tau0_s);
double model_mvar(const std::array<double, kNumLevels>& h, double tau_s, double tau0_s);

}  // namespace allanlot::kernels::powerlaw
