// Model-discrepancy diagnosis (docs/diagnose.md): where a noise model disagrees
// with a measured channel, which effect is missing, and the model with that effect added.
//
// Where. The measured overlapping Allan variance (NIST SP1065 eq. (11)) on a log tau grid is
// compared with the model's prediction model_avar_sampled() tau by tau:
//
//   z_i = ln(avar_hat_i / avar_model_i) / sqrt(2 / edf_i),   gap = sqrt(mean_i z_i^2),
//
// edf_i the EDF of the estimate under the model being tested (diagnose_model_edf: Greenhall &
// Riley's for the model's own power laws and effects, never the measured curve's noise
// identification, which a line or the last few averages can inflate 10-200 fold; Greenhall &
// Riley, "Uncertainty of stability variances based on finite differences", PTTI 2003), since edf *
// avar_hat / avar is chi-square with edf degrees of freedom (SP1065 sec. 5.3.3) and var(ln chi2_nu
// / nu) ~ 2 / nu. A correct model gives gap ~ 1.
//
// Correlation of neighbouring taus. Overlapping estimates at neighbouring taus share most of
// their data (correlation 0.9 and more at 16 taus per decade, kernels/model/fit.hpp), so a noise
// excursion spans several taus and a sum of z^2 over P taus varies far more than a chi-square
// with P degrees of freedom. The correlation matrix C of the estimates is computed from the
// eq. (3) noise model fitted to the measurement (OavarCovariance, exact for Gaussian noise),
// and the effective number of independent taus is Satterthwaite's (Box 1954, "Some theorems on
// quadratic forms applied in the study of analysis of variance problems", Ann. Math. Stat. 25):
//
//   n_eff = P^2 / sum_ij C_ij^2,
//
// which matches the mean and variance of sum z_i^2 to a scaled chi-square with n_eff degrees of
// freedom. It is used twice: (1) a tau is significant when its two-sided chi-square p-value is
// below band_alpha / n_eff (Bonferroni over the independent taus), so that a complete model
// shows any band with probability about band_alpha; the exact chi-square tail is used rather
// than |z| because at the longest taus edf is a few units and ln chi2 is strongly skewed;
// (2) the information criterion below scales chi-square differences by n_eff / P.
//
// Why. Candidates are the five terms of eq. (3) and three effects outside it:
//   quantization (Q), white (N), flicker (B), random_walk (K), ramp (R)  -- 1 parameter each,
//   sinusoid  (amplitude, frequency_hz): a bump at tau ~ 0.37 / f, decaying with ripples;
//   markov    (sigma, tau_c_s): +1/2 then -1/2 ADEV slopes around tau ~ 1.9 tau_c;
//   lowpass   (cutoff_hz or taps): the sensor's filter, a deficit of the white noises at the
//             shortest taus (kernels/simulate/lowpass.hpp), 1 parameter;
//   step      (size, time_s): a bias jump, a random-walk-like rise of the Allan variance that
//             falls with the record's length (step_avar_sampled), 2 parameters;
//   resonance (sigma, frequency_hz, q): narrowband noise (kernels/simulate/resonance.hpp), a
//             sinusoid-like bump with ripples near tau ~ 0.37 / f0 whose ripples fade beyond the
//             coherence time q / (pi f0), 3 parameters.
// A candidate is fitted together with the model's coefficients (non-negative least squares
// on the variances, reweighted, as kernels/model/fit.hpp), its nonlinear parameter by a grid plus
// golden-section search (markov tau_c) or from the PSD (sinusoid frequency). The fit quality
// is the chi-square of the log residuals with the exact moments of ln(chi2_nu / nu): mean
// psi(nu/2) - ln(nu/2), variance psi'(nu/2) (Bartlett & Kendall 1946, "The statistical
// analysis of variance-heterogeneity and the logarithmic transformation", JRSS Suppl. 8), and
// the criterion is
//
//   delta_ic = (chi2_reference - chi2_candidate) n_eff / P - c_k,
//   c_k = chi-square quantile at 1 - select_alpha / 10 with k degrees of freedom
//         (k counts the parameters fitted on the curve: none for a witnessed effect below),
//
// a penalized criterion like AIC (c_k = 2k) and BIC (c_k = k ln n) but with the penalty set by
// the level of the test it implies: with n_eff ~ 8, BIC's ln(8) per parameter would let a
// complete model pick up one of the ten candidates in about a fifth of records. A candidate
// is added only when delta_ic > 0, so a model that already fits gets nothing. Each candidate
// is tried with the model's coefficients fixed (reference: the model as it stands) and
// re-estimated (reference: the model re-estimated with nothing added, so that the effect pays
// for itself beyond the re-estimation).
//
// Time-domain witness. A step is evaluated only when the change-point test find_step finds a
// jump in the record, from which its size and time are taken (the Allan curve cannot place it
// in time, and a random walk or ramp would mimic its rise there). A witnessed effect (step,
// sinusoid, or a ramp of the record's slope) pays no penalty c_k: its false alarm is the
// witness's own (step_false_alarm, line_false_alarm, trend_false_alarm per record). It is named
// when the curve agrees better with it (delta_ic > 0), or, when a round would name nothing else,
// when the curve does not veto it (delta_ic > -3.84, chi2(1) at the verdict's 5 %): where the
// model is already within noise the curve sees the effect at a fraction of a sigma
// (docs/diagnose.md, "A witness against a model within noise").
//
// PSD witness. A sinusoid is a line in the spectrum, which the Allan variance smears into a
// bump that a Gauss-Markov hump can mimic. The sinusoid candidate is therefore only evaluated
// when the full-record periodogram shows a significant line (find_spectral_line), and its
// frequency is taken from that line (resolution 1/T, far finer than the Allan bump's), so
// that the frequency is estimated where it is identifiable.
//
// Add and repeat. The winner is added with its parameters, and the search repeated until no
// candidate has delta_ic > 0 (or max_effects are added). Re-estimating the coefficients with
// nothing added is a hypothesis of its own, taken only when no effect is significant
// (incomplete before wrong: a raised flicker floor can mimic two hidden effects at once). At
// the end the given coefficients are tested, fixed at their given values versus re-estimated
// with every added effect in place (the chi-square gain matched to c chi2_nu by its own
// Satterthwaite match of the change it tests, at select_alpha); when re-estimating is
// significant the given coefficients were wrong (reported with given and estimated values),
// otherwise the given values are kept. A model that ends beyond its replicas' p95 (with 19
// replicas or more) gets one more round at the verdict's 5 % among the effects a witness beside
// the curve attests, kept only if the model then ends within noise (docs/diagnose.md).
//
// Simulation vs measurement. The model before and after is simulated mc_replicas times at the
// measurement's length and rate (SimulationPlan; replica r is stream r of mc_seed, so the result
// does not depend on the thread count); the per-tau quantiles of the replicas' overlapping Allan
// variance give a Monte Carlo band, and the replicas' gaps against the analytic model give the
// null distribution of the gap, from which "within statistical noise" is judged.
#pragma once

#include "kernels/allan/stat_result.hpp"
#include "kernels/model/terms.hpp"
#include "kernels/simulate/simulate.hpp"

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// The effect vocabulary of docs/diagnose.md.
enum class Effect {
  Quantization,
  White,
  Flicker,
  RandomWalk,
  Ramp,
  Sinusoid,
  Markov,
  Lowpass,
  Step,
  Resonance
};
inline constexpr int kNumEffects = 10;

/// The eq. (3) terms' names (quantization, white, flicker, random_walk, ramp) and each other
/// effect's EffectTraits name (kernels/model/effects/).
std::string_view effect_name(Effect e);
/// Inverse of effect_name; nullopt for anything else.
std::optional<Effect> parse_effect(std::string_view name);
/// The eq. (3) term an effect adds (Q, N, B, K, R); nullopt for the others.
std::optional<Term> effect_term(Effect e);

/// The largest DiagnoseOptions::max_effects (diagnose --max-effects, allanlot.diagnose).
inline constexpr int kMaxEffects = 32;

struct DiagnoseOptions {
  int taus_per_decade = 8;    // log tau grid of the comparison (kernels/allan/tau_grid.hpp log:K)
  int mc_replicas = 30;       // Monte Carlo replicas per model (0 = no band)
  std::uint64_t mc_seed = 7;  // seed of the replicas; replica r is Philox stream r
  // Simulate the model as given too (Diagnosis::mc_before, its band and gap distribution). Nothing
  // that decides the corrected model or its verdict reads those replicas: off, mc_before stays
  // empty and the model, the effects named and mc_after are the same (when the model is not
  // corrected, mc_after is simulated rather than copied from mc_before, with the same seed).
  bool mc_given = true;
  double band_alpha = 0.05;        // probability that a complete model shows any band
  double select_alpha = 0.05;      // probability that a round adds an effect to a complete model
  double line_false_alarm = 1e-4;  // probability of a spurious PSD line in the whole record
  double step_false_alarm = 1e-3;  // probability of a spurious jump in the whole record
  // Probability of a spurious trend per witnessed test under the model as given. The model's
  // low-frequency power is itself estimated from the few averages of the longest taus, which
  // makes the real rate higher: at 1e-3 one realisation of the study's strong hump (600 s,
  // tau_c 20 % off) had z = -3.40 and was named a ramp.
  double trend_false_alarm = 1e-4;
  // At most this many effects are added, 1 .. kMaxEffects. A real accelerometer shows several
  // lines, its filter, a bias jump and a hump (docs/diagnose.md "Real sensors"); four left some
  // unnamed.
  int max_effects = 8;
  int nthreads = 0;  // 0 = OpenMP default; results do not depend on it
};

/// A parameter with its 1-sigma uncertainty, under the model file's own key.
struct Parameter {
  std::string name;  // "K", "amplitude", "frequency_hz", "sigma", "tau_c_s", ...
  double value = 0;
  double sigma = 0;  // NaN when not estimable (e.g. held at zero, or at a search bound)
  // 0: an estimate; -1: at the lower end of its search range, so only an upper limit
  // ("tau_c_s < value"); +1: at the upper end, a lower limit. A bound has no sigma.
  int bound = 0;
};

/// A run of consecutive significant taus with the same sign of disagreement.
struct Band {
  std::size_t first = 0, last = 0;  // indices into the tau grid
  double tau_lo_s = 0, tau_hi_s = 0;
  int sign = 0;          // +1: measurement above the model, -1: below
  double max_abs_z = 0;  // largest |z| inside
};

/// The measurement against one model, tau by tau.
struct Comparison {
  std::vector<double> avar_model;         // model_avar_sampled at each m [u^2]
  std::vector<double> z;                  // docs/diagnose.md's z
  std::vector<double> p_value;            // two-sided chi-square p-value of each tau
  std::vector<std::uint8_t> significant;  // p_value < band_alpha / n_eff
  double gap = 0;                         // sqrt(mean z^2)
  std::vector<Band> bands;
};

/// The quantile of a model's replicas' gaps that a measured gap is judged by ("within
/// statistical noise" below it), at the plotting position that a fresh draw exceeds with
/// probability 1 - kGapNoiseQuantile (exceedance_quantile_sorted); lot_noise.hpp gives that
/// chance for a given number of replicas.
inline constexpr double kGapNoiseQuantile = 0.95;

/// Monte Carlo replicas of one model at the measurement's length and rate.
struct McBand {
  int replicas = 0;
  // per-tau 5 %, 50 %, 95 % quantiles (of the replicas with the model's steps added)
  std::vector<double> avar_lo, avar_median, avar_hi;
  std::vector<double> gaps;  // each replica's gap against the analytic model (measured edf)
  double gap_median = 0;
  double gap_p95 = 0;  // exceedance_quantile_sorted(gaps, kGapNoiseQuantile)
};

/// The verdict (Diagnosis::gap_within_noise): a model's gap is within the noise of its
/// replicas when it is at most their gap_p95; without replicas, when it is at most 1.
inline bool within_noise(double gap, const McBand& mc) {
  return mc.replicas > 0 ? gap <= mc.gap_p95 : gap <= 1.0;
}

/// The strongest line of the full-record periodogram (the PSD witness).
struct SpectralLine {
  bool searched = false;       // false when the record has gaps or is too short
  bool found = false;          // peak / background above the threshold
  double frequency_hz = 0;     // interpolated peak frequency
  double sigma_hz = 0;         // Cramer-Rao bound of the frequency (Rife & Boorstyn 1974)
  double amplitude = 0;        // sqrt(2 x line power above the background) [u]
  double amplitude_sigma = 0;  // Cramer-Rao bound of the amplitude, sqrt(S1 / T) (same source)
  double peak_ratio = 0;       // periodogram / local mean background at the peak bin
  double threshold = 0;        // ln(bins / line_false_alarm)
  double resolution_hz = 0;    // bin spacing 1 / T
  // The first significant peak wider than a line (a narrowband process), 0 when none, and its
  // fit as a resonance's PSD (Whittle's likelihood on the bins around it): found when the fit
  // converged with q inside (2, the frequency over two bins).
  double wide_hz = 0;
  struct Narrowband {
    bool found = false;
    double frequency_hz = 0, frequency_sigma = 0;  // the resonance's f0 and its 1-sigma
    double q = 0, q_sigma = 0;
    double sigma = 0, sigma_sigma = 0;  // stationary sd of the peak's process [u] (as measured)
    double spread_hz = 0, spread_sigma = 0;  // a wandering resonance's spread (0: stationary)
  } narrowband;
};

/// Searches the one-segment Hann periodogram of `rate` (no NaN) for its most significant line
/// at least 8 bins from DC and away (4 bins) from each frequency in `known_hz`. Background: the
/// median of the 128 surrounding bins (the central 7 excluded) divided by ln 2, the mean of an
/// exponential with that median; for a locally monotone spectrum the median of a symmetric
/// window is the central value, so power-law slopes do not bias it. Under noise, a bin over its
/// background is exponential (chi-square 2 / 2), so the largest of M bins exceeds t with
/// probability about M e^-t, and the threshold is t = ln(M / false_alarm).
SpectralLine find_spectral_line(std::span<const double> rate, double rate_hz,
                                std::span<const double> known_hz, double false_alarm = 1e-4,
                                int nthreads = 0);

/// The most significant bias jump of a record (the step's time-domain witness).
struct StepWitness {
  bool searched = false;     // false when the record has gaps or fewer than 68 samples
  bool found = false;        // p_value < false_alarm, not a spike, not at a known step
  double time_s = 0;         // the jump's time after the first sample's start
  double time_sigma_s = 0;   // the finest scale at which it stands out by 3 rms [s]
  double size = 0;           // the jump [u], signed
  double size_sigma = 0;     // rms of the differences of adjacent means at the best scale,
                             // with the triangle's drop over half the time's uncertainty
  std::int64_t scale_m = 0;  // the best scale (samples per mean)
  double statistic = 0;      // |D - mean| / rms at the best scale
  double p_value = 1;        // the largest of the windows' tail (Pickands), times the scales
  double false_alarm = 0;
  std::string note;  // why a large excursion is not a jump
};

/// Searches `rate` (no NaN) at rate_hz, with the `known` steps removed, for its most significant
/// bias jump by a change-point test on the differences of adjacent means at scales 1, 2, 4, ...
/// samples (kernels/diagnose/find_step.cpp): Student-t against the other windows' spread, the
/// maximum over the windows by Pickands' tail, Bonferroni over the scales, so about
/// `false_alarm` per record or less for any Gaussian
/// noise of stationary increments (white, flicker, random walk, Gauss-Markov) with no model
/// needed; spikes are told apart by their plateau. Throws std::invalid_argument for a bad rate
/// or false_alarm.
StepWitness find_step(std::span<const double> rate, double rate_hz, std::span<const Step> known,
                      double false_alarm = 1e-3);

/// The ramp's witness: the record's least-squares slope against its standard deviation under
/// the model being tested (kernels/diagnose/find_trend.cpp).
struct TrendWitness {
  bool searched = false;  // false when the record has gaps or fewer than 3 samples
  bool found = false;     // p_value < false_alarm
  double slope = 0;       // least-squares slope of the record [u/s]
  double sigma = 0;       // its standard deviation under the model [u/s]
  double z = 0;           // slope / sigma
  double p_value = 1;     // two-sided, of a normal z
  double false_alarm = 0;
};

/// Variance of the least-squares slope of a record of duration_s under the model's noise (its
/// one-sided PSD, model_psd_one_sided; ramp and lines left out) [(u/s)^2]. Throws
/// std::invalid_argument for a duration that is not finite and > 0.
double trend_slope_variance(const ChannelSpec& model, double duration_s);

/// The least-squares slope of samples at rate_hz against time [u/s] (at least 2 samples).
double least_squares_slope(std::span<const double> y, double rate_hz);

/// Tests `rate` (its known steps removed) for a trend the model does not explain: a ramp's
/// witness at `false_alarm` per test. Not searched for a record with NaN or under 3 samples.
/// Throws std::invalid_argument for a bad rate_hz or false_alarm.
TrendWitness find_trend(std::span<const double> rate, double rate_hz, const ChannelSpec& model,
                        double false_alarm = 1e-3);

/// One candidate effect as evaluated in one iteration.
struct Candidate {
  Effect effect = Effect::White;
  bool evaluated = false;
  std::string note;                   // why not evaluated, or the PSD witness's verdict
  double delta_ic = 0;                // > 0: significant improvement
  std::vector<Parameter> parameters;  // the effect's estimated parameters
};

/// One round of the add-and-repeat loop.
struct Iteration {
  Effect effect = Effect::White;        // the effect added
  std::vector<Parameter> parameters;    // its parameters (model file keys) with uncertainties
  std::vector<Parameter> coefficients;  // every coefficient of the refitted model
  double delta_ic = 0;
  double gap_before = 0, gap_after = 0;
  std::vector<Band> bands_before, bands_after;
  std::vector<Candidate> candidates;  // every candidate of this round
  ChannelSpec model_after;
};

/// A coefficient the given model had, fixed versus re-estimated (at the end).
struct Revision {
  std::string name;  // "N", "K", ..., "sinusoid[0].amplitude", "markov[0].sigma"
  double given = 0, estimated = 0, sigma = 0;
};

struct Diagnosis {
  // The measurement on the comparison grid.
  std::vector<std::int64_t> m, n;
  std::vector<double> tau_s, avar_measured;
  std::vector<double> edf;        // edf of each estimate under the given model (diagnose_model_edf)
  std::vector<double> edf_after;  // the same under the corrected model
  double n_eff = 0;               // effective number of independent taus
  double penalty = 0;             // the criterion's penalty c_1 for a one-parameter candidate
  double z_threshold = 0;         // |z| of a normal variate at the per-tau significance level

  ChannelSpec model_before, model_after;
  Comparison before, after;
  McBand mc_before, mc_after;
  SpectralLine line;   // the first iteration's PSD witness
  StepWitness step;    // the first iteration's time-domain witness
  TrendWitness trend;  // the ramp's witness under the given model (not searched if it has a ramp)
  std::vector<Iteration> iterations;
  std::vector<Effect> effects_named;
  // Effects' final parameters with uncertainties, in effects_named order.
  std::vector<std::vector<Parameter>> effect_parameters;
  bool coefficients_wrong = false;  // the given coefficients differ significantly from the data
  double revision_delta_ic = 0;
  std::vector<Revision> revisions;  // every coefficient the given model had
  bool gap_within_noise = false;    // gap_after <= mc_after.gap_p95 (or <= 1 without replicas)
  std::vector<std::string> notes;
};

/// Diagnoses the rate samples `rate` (NaN = gap) at rate_hz against `model` (its rate_hz is
/// replaced by rate_hz). Throws std::invalid_argument for a bad model, a record too short for
/// three octaves of taus, or a model whose variance is zero at some tau.
Diagnosis diagnose(std::span<const double> rate, double rate_hz, const ChannelSpec& model,
                   const DiagnoseOptions& opt = {});

/// `model` (a Diagnosis::model_after) fitted again on `oadev`, the overlapping Allan deviation
/// of the record of n_samples it was diagnosed on, with its edf (kernels::add_confidence), jumps
/// included: the levels of the noise terms, humps and resonances (non-negative least squares on
/// the variances, as diagnose fits them, weighted by that edf), a filter's form and value, each
/// hump's tau_c and each resonance's f0 and q searched near their values; the model's jumps,
/// lines and rounding stay as they are, their share of each tau known. A Gauss-Markov hump and a
/// resonance (started from the periodogram of `rate`, the record's samples, when given) are
/// added, each at most once, where the curve's chi-square asks for them by diagnose's selection
/// criterion; they come after the model's own in the returned spec. The curve to draw beside
/// `oadev` and the coefficients to report with it (kernels/diagnose/refit.cpp). `model` itself
/// when fewer than 4 taus have a variance. Throws std::invalid_argument for a bad model.
ChannelSpec fit_to_curve(const ChannelSpec& model, const StatResult& oadev, std::int64_t n_samples,
                         std::span<const double> rate = {});

/// The edf of the overlapping Allan variance at each averaging factor in `m` over a record of
/// n_samples, under `model` (docs/diagnose.md "Where"): each noise term and Gauss-Markov effect
/// has the Greenhall & Riley edf (kernels/uncertainty/edf.hpp) of its power law (a Gauss-Markov
/// effect the local one of its Allan variance's slope), their standard deviations combined at
/// most linearly (so never overstated), the ramp and sinusoids adding their cross term with the
/// noise, and the result at most the largest edf of any power law at that m and length. Throws
/// std::invalid_argument for a bad model or an m without an estimate.
std::vector<double> diagnose_model_edf(const ChannelSpec& model, std::span<const std::int64_t> m,
                                       std::int64_t n_samples);

/// gap = sqrt(mean z^2) with the z of docs/diagnose.md "Where", for avar_measured against
/// avar_model.
double diagnose_gap(std::span<const double> avar_measured, std::span<const double> avar_model,
                    std::span<const double> edf);

/// The sensor's filter as analyze's eq. (3) fit needs it, named from a
/// measured overlapping Allan curve alone by diagnose's own test: the five terms of eq. (3),
/// all re-estimated, against the same with diagnose's lowpass candidate (first-order cutoffs
/// from rate / 200 to 0.45 rate, moving averages of 1.05 to 16 samples, 8 per octave, the best
/// refined between its neighbours; the model's edf; docs/diagnose.md "The sensor's filter"), named
/// when its criterion delta_ic > 0, the level of one diagnose round (select_alpha / 10 per
/// candidate).
struct LowpassFinding {
  Lowpass filter;  // inactive when no filter is significant
  // the candidate's criterion (> 0: named); NaN when not evaluated (too few taus)
  double delta_ic = std::numeric_limits<double>::quiet_NaN();
};

/// `oadev` with its edf (kernels::add_confidence) of a channel of n_samples rate samples at
/// rate_hz; n_eff the effective number of independent taus of `oadev` (effective_taus_of of the
/// eq. (3) fit's covariance), or 0 to compute it here (one covariance model, about 0.2 s).
/// Fewer than 7 taus with a positive variance: no filter. Throws std::invalid_argument for a
/// rate or length that is not positive.
LowpassFinding find_lowpass(const StatResult& oadev, double rate_hz, std::int64_t n_samples,
                            double n_eff = 0.0, double select_alpha = 0.05);

}  // namespace allanlot::kernels
