// The types and functions diagnose's sources share (candidates.cpp, search.cpp, diagnose.cpp,
// conclude.cpp and the others of this folder); not part of the interface (diagnose.hpp).
#pragma once

#include "kernels/diagnose/component.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/model/terms.hpp"
#include "kernels/spectral/psd.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::kernels::diagnose_detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Every effect in Effect's order: a round's candidates, each in its slot.
inline constexpr std::array<Effect, kNumEffects> kAllEffects = [] {
  std::array<Effect, kNumEffects> out{};
  for (int e = 0; e < kNumEffects; ++e)
    out[static_cast<std::size_t>(e)] = static_cast<Effect>(e);
  return out;
}();

// The measured curve on the comparison grid with the exact moments of its logarithm:
// for edf * avar_hat / avar ~ chi2_nu, E ln(avar_hat / avar) = psi(nu/2) - ln(nu/2) (about
// -1/nu) and var = psi'(nu/2) (about 2/nu), so ln_y below is unbiased for ln avar and var_ln its
// variance; at edf ~ 3 the bias is -0.37 and the variance 1.4 times 2/nu, which matters for the
// longest taus.
struct Curve {
  std::vector<std::int64_t> m, n;
  std::vector<double> tau, y, edf, ln_y, var_ln;
  // Greenhall-Riley edf of each power law alpha = -2..2 (index alpha + 2) at each m, and the
  // largest of them: the most any estimate at that m can have (prepare_edf).
  std::array<std::vector<double>, 5> edf_pl;
  std::vector<double> edf_cap;
  double tau0 = 1.0;
  std::int64_t n_samples = 0;
  std::size_t size() const { return m.size(); }
};

// Basis curves: the avar of each component with unit coefficient, from model_avar_sampled so
// that the diagnosis uses exactly the theory the simulator is tested against. The five term
// bases are computed once (flicker's sampling factor is a quadrature).
// Under a low-pass filter (a named or given lowpass) the white FM and white PM bases and every
// sinusoid's carry the filter's factors (model_avar_sampled); bases_for gives the bases of a
// set of components from the unfiltered ones.
// The output's rounding (ChannelSpec::quantum) is known, not fitted: its avar, quantum^2 / (12 m),
// is `fixed`, added to every model curve and never filtered (the sensor rounds after its filter).
struct Bases {
  std::array<std::vector<double>, kNumTerms> term;
  std::vector<double> fixed;  // the rounding's avar at each tau (all zero without a quantum)
  double rate_hz = 1.0;
  Lowpass lowpass;
};

// A fitted set of components.
struct Fit {
  std::vector<Component> comps;
  std::vector<double> model;  // avar of the components at each tau
  double chi2 = 0.0;          // sum (ln_y - ln model)^2 / var_ln
};

// The two witnesses of a round: the PSD's strongest unexplained line and the record's most
// significant unexplained jump.
struct Witnesses {
  SpectralLine line;
  StepWitness step;
  const Curve* without_jump = nullptr;     // the curve with the jump removed (step.found)
  const PsdResult* periodogram = nullptr;  // the record's (none with gaps)
  double line_false_alarm = 1e-4;
  std::span<const double> record;  // the record, with its periodogram (a wander's track)
};

struct CandidateFit {
  Candidate info;
  Fit fit;
  std::size_t added = 0;  // index of the added component in fit.comps
  // How far below zero the criterion of a line or jump its witness found may fall before the
  // curve vetoes it (Search::witnessed_tolerance, Search::not_vetoed); 0 for the others.
  double tolerance = 0.0;
};

// The selection criterion of a round (see diagnose.hpp): chi-square differences scaled by
// n_eff / P, against the chi-square quantile at 1 - alpha_candidate with k degrees of freedom.
struct Criterion {
  double scale = 1.0;            // n_eff / P
  double alpha_candidate = 0.0;  // select_alpha / kNumEffects
  double n_eff = 1.0;
  double rate_hz = 1.0;
};

/// A new component of part p whose level is fitted and shape searched.
Component searched_component(Part p);
/// A jump as a component, pinned (never refitted on the curve).
Component step_component(const Step& st);

/// The chi-square quantile at 1 - alpha with k degrees of freedom; 0 for k = 0 (a witnessed
/// effect, whose parameters are not fitted on the curve).
double threshold(int k, double alpha);

/// The round's criterion of a candidate whose k parameters lower the chi-square by chi2_drop:
/// the drop scaled by n_eff / P, less the chi-square quantile at 1 - alpha_candidate.
inline double criterion(const Criterion& crit, double chi2_drop, int k) {
  return chi2_drop * crit.scale - threshold(k, crit.alpha_candidate);
}

// candidates.cpp: model components, their fits and the candidates.
/// The unfiltered term bases at the curve's taus and the rounding's avar of a quantum (>= 0).
Bases make_bases(const Curve& cv, double rate_hz, double quantum = 0.0);
/// `raw` (unfiltered bases) under filter lp: the N and Q bases times the filter's factors.
Bases filtered_bases(const Bases& raw, const Curve& cv, const Lowpass& lp);
/// The filter of a set of components (inactive when none is a lowpass).
Lowpass lowpass_of(const std::vector<Component>& comps);
std::vector<Component> components_of(const ChannelSpec& s);
ChannelSpec spec_of(const std::vector<Component>& comps, const ChannelSpec& like);
Fit fit_components(std::vector<Component> comps, const Curve& cv, const Bases& b);
/// The 1-sigma uncertainties of each component's coefficient, nonlinear parameter and q (NaN
/// where not estimated).
struct Sigmas {
  std::vector<double> coef, nl, q;
};
Sigmas fill_sigmas(const Fit& f, const Curve& cv, const Bases& b, double n_eff);
/// conclude.cpp: the orthogonal projector onto the span of a's columns (zero without columns).
Eigen::MatrixXd projector(Eigen::MatrixXd a);
/// A quadratic form u' Q u of u ~ N(0, corr) matched to c chi2_nu with its mean and variance
/// (Satterthwaite; Box 1954): c = tr((Q corr)^2) / tr(Q corr), nu = tr(Q corr)^2 / tr((Q corr)^2).
struct ScaledChi2 {
  double c = 1.0, nu = 0.0;  // nu = 0: no match (the form has no trace)
};
ScaledChi2 satterthwaite(const Eigen::MatrixXd& q, const Eigen::MatrixXd& corr);
/// The whitened columns of the free components of `comps` with a basis on the curve (a filter or
/// a step has none): each basis curve over sqrt(var_ln) times `model`, the derivative of the log
/// chi-square's residuals in the component's squared coefficient (P x k).
Eigen::MatrixXd free_columns(const std::vector<Component>& comps, std::span<const double> model,
                             const Curve& cv, const Bases& raw);
/// The parameters of component idx of a fit under the model file's keys, with their sigmas.
std::vector<Parameter> parameters_of(const Component& c, const Sigmas& sigmas, std::size_t idx);
std::string component_label(const std::vector<Component>& comps, std::size_t idx);
std::vector<double> model_curve(const ChannelSpec& s, const Curve& cv, const Bases& b);
/// The minimum of f on [a, c] by 25 golden-section steps (the interval shrinks to 6e-6 of
/// itself): the better of the last two points.
double golden_min(const std::function<double(double)>& f, double a, double c);
// markov.cpp: the search of a hump's tau_c, its Allan variance at the curve's taus under the
// filter `lp`, and its candidate (no fit and a note when refused).
Fit search_tau_c(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b);
std::vector<double> markov_curve(double sigma, double tau_c_s, const Curve& cv, const Lowpass& lp,
                                 double rate_hz);
/// The unit curve (coefficient 1) of a Markov or resonance component at the curve's taus under
/// b's filter: markov_curve or resonance_curve, computed once a thread for the same inputs
/// (curve_cache.cpp).
std::vector<double> shaped_curve(const Component& c, const Curve& cv, const Bases& b);
CandidateFit hump_candidate(std::vector<Component> comps, const Curve& cv, const Bases& b);
/// The lowpass candidate: a new filter searched with the others as `base` has them, and the
/// resonances named before it searched again under it.
CandidateFit lowpass_candidate(std::vector<Component> base, const Curve& cv, const Bases& b);
/// The filter of the lowpass component comps[idx] searched (both forms, a grid then refined),
/// the free coefficients fitted at each trial; `b` unfiltered.
Fit search_lowpass(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b);

// The significant candidate (evaluated, delta_ic > 0) with the largest criterion among those
// `pick` accepts (the first of equals); cands.size() when there is none.
template <class Pick>
std::size_t strongest(const std::vector<CandidateFit>& cands, Pick pick) {
  std::size_t best = cands.size();
  for (std::size_t c = 0; c < cands.size(); ++c)
    if (pick(cands[c].info.effect) && cands[c].info.evaluated && cands[c].info.delta_ic > 0.0 &&
        (best == cands.size() || cands[c].info.delta_ic > cands[best].info.delta_ic))
      best = c;
  return best;
}

/// Whether effect e is named on a witness in the record rather than fitted on the curve: a
/// registered effect whose EffectTraits::curve_parameters is 0 (a line, a jump).
bool witnessed_effect(Effect e);

/// choose.cpp: the markov candidate `best` gives way to a significant random walk or white
/// candidate when its turnover is not within the taus measured (`note` says so).
std::size_t prefer_nested(const std::vector<CandidateFit>& cands, std::size_t best, const Curve& cv,
                          std::string& note);

// resonance.cpp: the resonance's curve and its search.
/// The Allan variance of a resonance at the curve's taus under the filter lp.
std::vector<double> resonance_curve(const Resonance& r, const Curve& cv, const Lowpass& lp,
                                    double rate_hz);
/// frequency_hz and q of the resonance comps[idx] searched on the curve, the free coefficients
/// fitted at each; `grid` searches the whole range first, else only near the present values.
/// With `grid`, `others` (when given) receives the grid's other local minima over the frequency,
/// (f0, q) each, best first: at most kOtherStarts, an octave or more from the best and apart.
Fit search_resonance(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b,
                     bool grid, std::vector<std::pair<double, double>>* others = nullptr);
inline constexpr std::size_t kOtherStarts = 3;
/// The resonance candidate: a new component searched with the others as `base` has them; with a
/// note and no fit when it is not a distinct instance.
CandidateFit resonance_candidate(std::vector<Component> base, const Curve& cv, const Bases& b,
                                 const Witnesses& seen, const std::function<double(int)>& penalty);
CandidateFit witnessed_resonance(std::vector<Component> base, const SpectralLine::Narrowband& nb,
                                 const Curve& cv, const Bases& b);
/// The parameters a resonance's criterion charges (candidates.cpp).
int resonance_parameters(const Component& c);
/// Marks a fitted candidate (its component added last) evaluated: its criterion against
/// chi2_ref at k parameters (0 for a witnessed effect) and its parameters on `fit_cv`.
void score_candidate(CandidateFit& cf, int k, double chi2_ref, const Curve& fit_cv, const Bases& b,
                     const Criterion& crit);
/// Candidate e added to `comps` (their coefficients fixed or free as they are), fitted and
/// judged against chi2_ref; n_refit counts the parameters the reference's refit already frees.
CandidateFit evaluate_candidate(Effect e, std::vector<Component> comps, const Witnesses& seen,
                                int n_refit, double chi2_ref, const Curve& cv, const Bases& b,
                                const Criterion& crit);

// edf_model.cpp: the edf of the model under test (docs/diagnose.md "Where").
/// Fills cv.edf_pl and cv.edf_cap from cv.m and cv.n_samples.
void prepare_edf(Curve& cv);
/// The edf of the overlapping Allan variance at each tau of `cv` under model `s`.
std::vector<double> model_edf(const ChannelSpec& s, const Curve& cv, const Bases& b);
/// Sets cv.edf and the unbiased logarithms ln_y and their variances var_ln from it.
void use_edf(Curve& cv, std::vector<double> edf);

// measure.cpp: the measured curve of an overlapping Allan deviation with its edf (taus of
// zero variance dropped), edf capped at what the averages allow, ready for use_edf.
Curve curve_of(const StatResult& oadev, double rate_hz, std::int64_t n_samples);
/// The record's curve: overlapping Allan variance on a log grid of opt.taus_per_decade, with
/// its edf (curve_of); throws when fewer than 3 octaves of tau or 4 non-zero taus remain.
Curve measure(std::span<const double> rate, double rate_hz, const DiagnoseOptions& opt,
              int threads);

// search.cpp: the measurement against a model, the PSD witness and the Monte Carlo band.
Comparison compare(const Curve& cv, std::vector<double> model, const std::vector<double>& edf,
                   double alpha_tau);
McBand monte_carlo(const ChannelSpec& spec, const Curve& cv, const std::vector<double>& model,
                   const std::vector<double>& edf, int replicas, std::uint64_t seed, int threads);
double effective_taus(const Curve& cv);
/// The same from `corr`, the correlation of the curve's estimates (tau_correlation; empty: the
/// fallback of one tau per octave).
double effective_taus(const Curve& cv, const Eigen::MatrixXd& corr);
/// The correlation of the curve's estimates under the eq. (3) fit to it (the model covariance
/// OavarCovariance, kernels/model/fit.hpp); empty when that fit has no terms.
Eigen::MatrixXd tau_correlation(const Curve& cv);
// Each bin's background median for the line search (NaN where it has none).
std::vector<double> line_backgrounds(const PsdResult& psd, int threads = 1);
// The line search of find_spectral_line over the bins from f_lo_hz to f_hi_hz (all by default),
// against the backgrounds line_backgrounds(psd) gives.
SpectralLine search_line(const PsdResult& psd, std::span<const double> medians, double n_seconds,
                         std::span<const double> known, std::span<const double> known_wide,
                         double false_alarm, double f_lo_hz = 0.0,
                         double f_hi_hz = std::numeric_limits<double>::infinity());
// The median of the periodogram over the bins lo <= |j - k| <= hi inside [1, kmax], gathered
// in `buf` (its size is the number of bins): the line search's background and the width test's
// rings.
double ring_median(const PsdResult& psd, std::int64_t k, std::int64_t lo, std::int64_t hi,
                   std::vector<double>& buf);
// find_narrowband.cpp: a significant peak wider than a line, and its fit as a resonance. The
// far ring (bins kFarRing / 4 to kFarRing from the peak) is the background a width is judged
// against; a wide peak's far ring is left out of the search for further lines.
inline constexpr std::int64_t kFarRing = 384;
bool wider_than_a_line(const PsdResult& psd, std::int64_t k);
SpectralLine::Narrowband fit_narrowband(const PsdResult& psd, std::int64_t k, double false_alarm);
// The shapes of a peak's resonances on the periodogram from f0 / 2 to 1.5 f0: the model's
// `present` resonances there and a new one near f0 (from each q of q_starts), fitted together
// over a log-linear background; the new one wandering where that is significant. The present
// ones' shapes (those outside the window unchanged, `found` false) then the new one's; empty
// when the new one is not significant at false_alarm (find_narrowband.cpp).
std::vector<SpectralLine::Narrowband>
fit_peak_shapes(const PsdResult& psd, const std::vector<SpectralLine::Narrowband>& present,
                double f0, const std::vector<double>& q_starts, double false_alarm);
// The periodogram's broad humps above f_lo_hz, strongest first, as (frequency, z) pairs: the
// local maxima of the excess of 1/16-octave bands over the median of the bands within half an
// octave, in standard deviations of a band's mean, from z = kBroadPeakZ, at most `count` of
// them and each half an octave or more from the ones before (find_narrowband.cpp).
inline constexpr double kBroadPeakZ = 3.0;
std::vector<std::pair<double, double>> broad_peaks(const PsdResult& psd, double f_lo_hz,
                                                   std::size_t count);
// The correlation time [s] of a wandering resonance's frequency from its track through `record`
// (find_narrowband.cpp).
double wander_time(std::span<const double> record, double rate_hz, double f0, double spread,
                   double q);
PsdResult full_periodogram(std::span<const double> rate, double rate_hz, int threads);
// The sample rate of a one-sided periodogram: twice its last bin's frequency.
inline double psd_rate_hz(const PsdResult& psd) {
  return 2.0 * static_cast<double>(psd.size() - 1) * psd.df_hz;
}
bool has_nan(std::span<const double> v);

}  // namespace allanlot::kernels::diagnose_detail
