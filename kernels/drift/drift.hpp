// Frequency drift: the deterministic part of a clock's (or sensor's) frequency that the Allan
// family should not see (docs/editing.md "Drift"). The models are Stable32's and NIST SP1065's
// ("Frequency Drift Analysis" and "Phase Drift Analysis"):
//   linear     y(t) = a + b t                fitted to the frequency (rate data)
//   quadratic  x(t) = a + b t + D t^2 / 2    fitted to the phase (phase data); y = b + D t
//   log        y(t) = a ln(b t + 1) + c      fitted to the frequency (aging of crystal units)
//   diffusion  y(t) = a + b sqrt(t + c)      fitted to the frequency (diffusion aging)
// with t = k tau0 the time of sample k from the first sample. The fit is ordinary least squares
// (the nonlinear b of log and c of diffusion by a one-parameter search around a linear solve).
//
// The parameters' sigma does not assume white residuals: a clock's frequency residuals are
// correlated (random-walk FM), and the white-noise formula understates a slope's uncertainty by
// a large factor there. Every estimate is (to first order) a linear functional sum_i w_i z_i of
// the fitted samples; its variance is computed under a noise model of white PM + white FM +
// random-walk FM whose three levels are fitted to the residuals' overlapping Allan variance.
#pragma once

#include "kernels/allan/phase.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// The drift models of `analyze --drift` (docs/cli.md).
enum class DriftModel { None, Linear, Quadratic, Log, Diffusion };

/// Parses none, linear, quadratic, log, diffusion; std::invalid_argument naming the text.
DriftModel parse_drift_model(std::string_view text);
std::string_view to_string(DriftModel model);

/// Levels of the noise model behind a drift's sigma, per sample: white PM variance of x
/// (phase units^2), white FM variance of y (rate units^2) and the variance of one random-walk
/// FM increment of y per sample (rate units^2). Allan variances (SP1065 Table 7, discrete
/// forms): 3 s_pm / tau^2, s_wfm tau0 / tau and s_rw (2 m^2 + 1) / (6 m) at tau = m tau0.
struct DriftNoise {
  double white_pm = 0, white_fm = 0, rw_fm = 0;
};

/// A fitted drift model.
struct DriftFit {
  DriftModel model = DriftModel::None;
  DataType fitted_to = DataType::Rate;  // the samples the model was fitted to
  std::vector<std::string> names;       // the parameters: e.g. offset, drift
  std::vector<double> value, sigma;     // their estimates and standard uncertainties
  DriftNoise noise;                     // the noise model behind sigma
  std::int64_t n_used = 0;              // samples fitted (valid ones)
};

/// The model's value at time t (seconds from the first sample): frequency for linear, log and
/// diffusion, phase for quadratic.
double drift_model_value(const DriftFit& fit, double t);

/// Fits `model` to `samples` (rate or phase, NaN samples left out) taken every tau0_s seconds.
/// Linear needs rate data and quadratic phase data (fit_drift_for picks the right one); log and
/// diffusion need rate data. Preconditions (std::invalid_argument naming the reason): tau0_s > 0,
/// at least 8 valid samples, a model that fits the data type.
DriftFit fit_drift(std::span<const double> samples, DataType type, double tau0_s, DriftModel model);

/// The model a user's choice means on this data type: linear and quadratic are one request, a
/// linear frequency drift, fitted as a line to frequency data and as a parabola to phase data.
DriftModel drift_model_for(DriftModel asked, DataType type);

/// Subtracts the fitted drift from `samples` in place, the model less its value at t = 0 (the
/// frequency offset, which the statistics remove anyway, is kept). NaN samples stay NaN.
void remove_drift(std::span<double> samples, double tau0_s, const DriftFit& fit);

/// Residuals of the samples against the whole fitted model (NaN where a sample is NaN).
std::vector<double> drift_residuals(std::span<const double> samples, double tau0_s,
                                    const DriftFit& fit);

/// The variance of sum_j v_j y_j + sum_i u_i x_i-noise under `noise`, where v are weights on
/// the n frequency samples y_j and the phase is x_i = tau0 sum_{j<i} y_j + e_i (i = 0..n):
/// white PM enters through u (the weights on the phase points' own noise e_i), white FM through
/// sum v^2, random-walk FM (y_j = sum_{k<=j} r_k) through sum_k (sum_{j>=k} v_j)^2.
double functional_variance(std::span<const double> v, std::span<const double> u,
                           const DriftNoise& noise);

/// The three noise levels fitted (non-negative least squares, weighted by each tau's degrees of
/// freedom) to the overlapping Allan variance of `residuals` (rate or phase, NaN = gap) at
/// octave taus up to a tenth of the record.
DriftNoise fit_drift_noise(std::span<const double> residuals, DataType type, double tau0_s);

}  // namespace allanlot::kernels
