// How long to record: the shortest record over which the eq. (3) fit measures a coefficient to
// a target precision, from the fit's own covariance rather than a rule of thumb.
//
// For a record of n samples of a noise model, the fit sees (on average) the model's overlapping
// Allan variance at the taus of the plan grid (16 per decade up to max_m), each estimate made
// of n + 1 - 2m terms with the Greenhall-Riley edf of the noise that dominates that tau
// (kernels/uncertainty/edf.hpp). Fitting that expected curve with kernels/model's Eq3Fit gives
// the sandwich covariance of the fitted squared coefficients at the true model (the honest
// sigma the fit reports, kernels/model/fit.hpp), and with it the coefficient's sigma
// sigma_theta / (2 value). The record is long enough when quantile * sigma / value <= the
// relative target. sigma falls with the record's length (more terms per tau, more taus on the
// branch), so the shortest such record is found by doubling n and then bisecting in n.
#pragma once

#include "kernels/model/fit.hpp"
#include "kernels/model/terms.hpp"
#include "kernels/simulate/simulate.hpp"

#include <cstdint>
#include <vector>

namespace allanlot::kernels {

/// The overlapping Allan variance a record of n_samples of a model shows on average, with what
/// the fit reads of each tau.
struct ExpectedCurve {
  std::vector<std::int64_t> m, n;  // averaging factor; terms n_samples + 1 - 2m
  std::vector<double> tau_s, avar, edf;
};

/// The plan grid's taus for a record of n_samples (>= 33) of `spec`: avar from
/// model_avar_sampled, edf from edf_greenhall for the power law of the term with the largest
/// share of avar at that tau (R and K: random walk, alpha -2; B: alpha -1; N: 0; Q: +2).
ExpectedCurve expected_curve(const ChannelSpec& spec, std::int64_t n_samples);

/// The fit of the expected curve: its terms' sigmas are the ones a fit of a record of that
/// length reports at the true model. Throws std::invalid_argument for n_samples < 33.
FitResult predicted_fit(const ChannelSpec& spec, std::int64_t n_samples, Eq3Fit& fitter);

/// What a record must measure: term to relative precision `relative` at the interval quantile
/// `quantile` (1.96 for 95 % two-sided).
struct LengthTarget {
  Term term = Term::B;
  double relative = 0.1;  // > 0
  double quantile = 1.959963984540054;
};

struct LengthPlan {
  bool reached = false;               // a record of at most max_samples meets the target
  std::int64_t n_samples = 0;         // the shortest record that does (the longest tried otherwise)
  double duration_s = 0;              // n_samples / rate
  double relative_sigma = 0;          // predicted sigma / value at that length
  double tau_lo_s = 0, tau_hi_s = 0;  // the taus where the term is at least half of avar
};

/// The target that decides a limit: a unit whose coefficient lies the fraction `margin` (0 <
/// margin < 1) inside `limit` (value = limit (1 - margin) under a max, limit (1 + margin) over a
/// min) is decided (pass) with probability `confidence` when the distance to the limit is
/// (z_{(1+c)/2} + z_c) sigma: the spec's two-sided interval (src/lot/spec.hpp) then lies inside
/// the limit unless the estimate strays outward by more than z_c sigma. relative is the
/// distance over the value, margin / (1 -+ margin). Sets *value.
LengthTarget limit_target(Term term, double limit, bool is_max, double margin, double confidence,
                          double* value);

/// The shortest record meeting `target` for `spec` (whose coefficient of target.term must be
/// > 0), to within 1 % in length, searched up to max_samples. Throws std::invalid_argument for a
/// zero coefficient or a target that is not > 0.
LengthPlan plan_length(const ChannelSpec& spec, const LengthTarget& target,
                       std::int64_t max_samples, Eq3Fit& fitter);

}  // namespace allanlot::kernels
