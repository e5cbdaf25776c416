// The end of a diagnosis (docs/diagnose.md "Why"): the final refit of the structure the rounds
// built, the pruning of effects that no longer pay for themselves, the test of the given
// coefficients, the model reported and the verdict against its replicas, with the verdict's own
// round when the model ends beyond noise.
#include "kernels/diagnose/internal.hpp"
#include "kernels/diagnose/rounds.hpp"
#include "kernels/uncertainty/chi2.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace allanlot::kernels::diagnose_detail {
namespace {

// The name of a given component's revision: the term's key, or "<effect>[i].<its level's
// model-file key>".
std::string level_key(const std::vector<Component>& comps, std::size_t idx) {
  const std::string label = component_label(comps, idx);
  return std::visit(
      [&label](const auto& p) {
        using E = std::decay_t<decltype(p)>;
        if constexpr (!std::is_same_v<E, TermLevel>)
          for (const auto& key : EffectTraits<E>::keys)
            if (key.field == EffectTraits<E>::level) return label + "." + std::string(key.name);
        return label;
      },
      comps[idx].part);
}

}  // namespace

// After the rounds: the final structure refitted, the given coefficients tested (fixed versus
// re-estimated), and the model after with its effects' parameters.
// The current structure with every coefficient re-estimated, under the edf of the model as it
// stands. Each added Markov effect's tau_c was searched in the round that named it, before the
// effects named after it were in the model (a quantization found later, say, had been partly
// absorbed by the hump); it is searched again with the final structure, and so are an added
// filter (first: it reshapes every other component's curve; a one-pole filter named in the first
// round, with a broad resonance beside it for the shape it lacked, gave way to the boxcar the
// ADIS16405 x gyroscopes have, and the resonance was pruned) and each resonance's f0 and q.
Fit Search::refit_final() {
  use_edf(cv, model_edf(spec_of(current, spec), cv, bases));
  std::vector<Component> all_free = current;
  for (Component& c : all_free)
    c.free = !c.pinned;
  return search_added(fit_components(all_free, cv, bases));
}

// The added effects' shapes searched again on `base`, with its coefficients free or fixed as
// they are: a filter's form and value, each hump's tau_c, each resonance's f0 and q.
Fit Search::search_added(Fit base) const {
  for (const std::size_t idx : added_idx)
    if (is<Lowpass>(base.comps[idx])) base = search_lowpass(base.comps, idx, cv, bases);
  for (const std::size_t idx : added_idx) {
    if (is<GaussMarkov>(base.comps[idx])) base = search_tau_c(base.comps, idx, cv, bases);
    if (is<Resonance>(base.comps[idx]) && !base.comps[idx].pinned && !base.comps[idx].psd_shape)
      base = search_resonance(base.comps, idx, cv, bases, false);
  }
  return base;
}

// The final structure with the given coefficients at their given values, the added effects'
// shapes searched under them: the model reported when the given coefficients are not found
// wrong, and the side of their test that keeps them. With the shapes searched beside
// re-estimated levels instead, the test compared each side at the other's best: a hump of
// tau_c 2 s injected into a real gyroscope's record (imu4 gyro_x, 7 sigma) was searched to
// 0.78 s beside free levels, fitted worse with the given ones at that tau_c (chi-square 60
// against 40 without it), had the given levels found wrong, and was then pruned because the
// re-estimated levels took it up.
Fit Search::refit_given_fixed(const std::vector<Component>& comps) const {
  return search_added(fit_given_fixed(comps, cv));
}

// `comps` with the given components back at their given values and fixed (the added effects
// still fitted).
std::vector<Component> Search::given_fixed(std::vector<Component> comps) const {
  for (std::size_t c = 0; c < given.size(); ++c) {
    comps[c] = given[c];
    comps[c].free = false;
  }
  return comps;
}

// The final structure fitted so, the added effects' shapes as they are.
Fit Search::fit_given_fixed(std::vector<Component> comps, const Curve& on) const {
  return fit_components(given_fixed(std::move(comps)), on, bases);
}

Eigen::MatrixXd projector(Eigen::MatrixXd a) {
  if (a.cols() == 0) return Eigen::MatrixXd::Zero(a.rows(), a.rows());
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    if (const double n = a.col(j).norm(); n > 0.0) a.col(j) /= n;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-10);
  const Eigen::MatrixXd u =
      qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), std::max<Eigen::Index>(qr.rank(), 0));
  return u * u.transpose();
}

ScaledChi2 satterthwaite(const Eigen::MatrixXd& q, const Eigen::MatrixXd& corr) {
  const Eigen::MatrixXd qr = q * corr;
  const double t1 = qr.trace(), t2 = (qr * qr).trace();
  if (!(t1 > 1e-9 && t2 > 0.0)) return {};
  return {t2 / t1, t1 * t1 / t2};
}

// The test of the given coefficients: the chi-square gain of re-estimating them, with the added
// effects fitted either way. To first order the gain is u' Q u, u the whitened residuals (of
// correlation R, tau_correlation) and Q the projector onto what the given coefficients change
// that the added effects cannot; Satterthwaite's match (Box 1954, as effective_taus) takes it as
// c chi2_nu (satterthwaite). The rounds' one scale,
// n_eff / P for the whole curve, understates a smooth change's spread: the white and flicker
// levels of a complete model were found wrong on 21 of 200 records (10.5 %) at a nominal 5 %.
// Without the correlation, the rounds' scale.
double Search::revision_criterion(const Fit& base, const Fit& fixed, int n_given) const {
  const double gain = fixed.chi2 - base.chi2;
  const double global = gain * crit.scale - threshold(n_given, opt.select_alpha);
  if (tau_corr.rows() != static_cast<Eigen::Index>(cv.size())) return global;
  const ScaledChi2 m =
      satterthwaite(projector(free_columns(base.comps, base.model, cv, bases)) -
                        projector(free_columns(fixed.comps, base.model, cv, bases)),
                    tau_corr);
  if (!(m.nu > 0.0)) return global;
  return gain / m.c - chi2_quantile(1.0 - opt.select_alpha, m.nu);
}

// Were the given coefficients wrong? The final structure with them fixed against all
// re-estimated (revision_criterion).
bool Search::given_wrong(const Fit& base, const Fit& fixed) {
  int n_given = 0;
  for (const Component& c : given)
    n_given += is<Lowpass>(c) ? 0 : 1;
  d.revision_delta_ic = n_given > 0 ? revision_criterion(base, fixed, n_given) : 0.0;
  d.coefficients_wrong = n_given > 0 && d.revision_delta_ic > 0.0;
  return d.coefficients_wrong;
}

// No phantom effects: after the final refit each added effect must still pay for
// itself, by the round's criterion (its removal, the rest refitted, must cost more than the
// penalty of its parameters). It is judged in the model that will be reported: with the given
// coefficients fixed unless they were found wrong (`free_given`). Judged with them always
// re-estimated, a small hump beside a complete model was lost: the free white and flicker
// levels took up part of it after the rounds had named it against the model as given (a
// Gauss-Markov hump of 5 sigma injected into a real gyroscope's record, 0 of 10). The least
// significant one that does not pay is removed and the model refitted; true when one was.
// Sinusoids, resonances named from a PSD peak wider than a line and steps are witnessed by
// their periodogram or their jump instead (their size is not fitted on the Allan curve), and are
// kept; a ramp, by the record's slope (below).
bool Search::prune(Fit& base, const Fit& fixed_fit, bool free_given) {
  const auto fit_on = [&](std::vector<Component> comps, const Curve& on) {
    return free_given ? fit_components(std::move(comps), on, bases)
                      : fit_given_fixed(std::move(comps), on);
  };
  // The rest refitted includes an added filter's form and value: a resonance or hump is judged
  // against the best filter without it, not the one chosen beside it. A one-pole filter named
  // beside a broad resonance (q at its bound) for the shape it lacked held the resonance in
  // place, while the boxcar alone, the 2-tap filter the ADIS16405 x and y gyroscopes have (lag-1
  // autocorrelation 0.17 to 0.29, none beyond), fits as well without it.
  const auto refit_without = [&](std::vector<Component> comps, const Curve& on) {
    for (std::size_t idx = given.size(); idx < comps.size(); ++idx) {
      if (!is<Lowpass>(comps[idx])) continue;
      if (!free_given) comps = given_fixed(std::move(comps));
      return search_lowpass(std::move(comps), idx, on, bases);
    }
    return fit_on(std::move(comps), on);
  };
  // The effects' shapes as searched in that model (refit_given_fixed).
  const std::vector<Component>& from = free_given ? base.comps : fixed_fit.comps;
  const Fit with = fit_on(from, cv);
  double worst = 0.0;
  std::size_t worst_k = added_idx.size();
  for (std::size_t k = 0; k < added_idx.size(); ++k) {
    const Component& c = with.comps[added_idx[k]];
    if (is<Sinusoid>(c) || is<Step>(c) || (is<Resonance>(c) && c.pinned)) continue;
    std::vector<Component> without = from;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(added_idx[k]));
    // Judged as the round judged it: under the edf of the model without the effect, the
    // hypothesis it is tested against, refitted as the rounds' models are (the coefficients
    // fitted beside the effect can be far from its own: the quantization a filter had traded
    // against). Under the edf of the model with it, a narrowband resonance's few degrees of
    // freedom (2 pi f0 T / q) made its own misfit cheap: a real accelerometer's 0.56 Hz
    // resonance was removed at criterion -9.8, the gap going from 0.99 at the end of the rounds
    // to 12.2.
    const ChannelSpec null_model = spec_of(refit_without(without, cv).comps, spec);
    // A ramp is kept while its witness, the record's slope, still sees it beside the rest of the
    // final model (named on the curve, one of the study's ten ramp + markov records lost it at
    // criterion -0.85); one named by the witness alone goes when the witness no longer sees it
    // (judged beside effects the pruning has since removed, the slope of one strong hump's
    // record stood at z = -4.06 and then at -3.4).
    if (is_term(c, Term::R) && coef(c) > 0.0) {
      if (trend_under(null_model).found) continue;
      if (c.pinned) {
        worst = -std::numeric_limits<double>::infinity();
        worst_k = k;
        continue;
      }
    }
    Curve null_cv = cv;
    use_edf(null_cv, model_edf(null_model, cv, bases));
    const Fit f = refit_without(without, null_cv);
    const Fit w = fit_on(from, null_cv);
    const int k_c = is<TermLevel>(c) || is<Lowpass>(c) ? 1
                    : is<Resonance>(c)                 ? resonance_parameters(c)
                                                       : 2;
    const double delta = criterion(crit, f.chi2 - w.chi2, k_c);
    if (!(coef(c) > 0.0) || delta <= worst) {
      worst = !(coef(c) > 0.0) ? -std::numeric_limits<double>::infinity() : delta;
      worst_k = k;
    }
  }
  if (worst_k == added_idx.size()) return false;
  const std::size_t idx = added_idx[worst_k];
  removed.push_back(d.effects_named[worst_k]);
  d.notes.push_back(std::string(effect_name(d.effects_named[worst_k])) +
                    " removed after the final refit: not significant with the other effects in "
                    "place (criterion " +
                    std::to_string(worst) + ")");
  current = base.comps;
  current.erase(current.begin() + static_cast<std::ptrdiff_t>(idx));
  added_idx.erase(added_idx.begin() + static_cast<std::ptrdiff_t>(worst_k));
  d.effects_named.erase(d.effects_named.begin() + static_cast<std::ptrdiff_t>(worst_k));
  for (std::size_t& a : added_idx)
    if (a > idx) --a;
  base = refit_final();
  return true;
}

// The final refit and the pruning, until every added effect pays for itself; true when one was
// removed. The last test of the given coefficients is that of the final structure: prune ends by
// returning false after it.
bool Search::settle(Fit& base, Fit& fixed_fit) {
  base = refit_final();
  fixed_fit = refit_given_fixed(base.comps);
  bool any = false;
  while (prune(base, fixed_fit, given_wrong(base, fixed_fit))) {
    fixed_fit = refit_given_fixed(base.comps);
    any = true;
  }
  return any;
}

void Search::finish() {
  Fit base, fixed_fit;
  // A removal changes what the rest leaves unexplained: the rounds resume once from the settled
  // model (the removed effects not named again), and what they name is settled in turn. Without
  // this, the corrected model of a real z accelerometer (imu6), re-diagnosed, named the 1.69 Hz
  // resonance its own diagnosis had left once the pruning removed its quantization.
  if (settle(base, fixed_fit)) {
    current = base.comps;
    const std::size_t before = d.iterations.size();
    run_rounds();
    if (d.iterations.size() > before) {
      std::string named;
      for (std::size_t i = before; i < d.iterations.size(); ++i)
        named += (named.empty() ? "" : ", ") + std::string(effect_name(d.iterations[i].effect));
      d.notes.push_back("the rounds resumed after the removal and named " + named);
      settle(base, fixed_fit);
    }
  }
  conclude(base, fixed_fit);
}

// The settled model reported: the given coefficients' revisions, the model after with its
// effects' parameters and its comparison with the measurement.
void Search::conclude(Fit& base, Fit& fixed_fit) {
  d.revisions.clear();
  d.effect_parameters.clear();
  const std::vector<double> cs = fill_sigmas(base, cv, bases, d.n_eff).coef;
  for (std::size_t c = 0; c < given.size(); ++c) {
    if (is<Lowpass>(given[c])) continue;  // given filters are kept as they are
    d.revisions.push_back(
        {level_key(given, c), signed_level(given[c]), signed_level(base.comps[c]), cs[c]});
  }
  Fit& final_fit = d.coefficients_wrong ? base : fixed_fit;
  if (d.effects_named.empty() && !d.coefficients_wrong) {
    d.model_after = spec;
  } else {
    d.model_after = spec_of(final_fit.comps, spec);
  }
  const Sigmas final_sig = fill_sigmas(final_fit, cv, bases, d.n_eff);
  for (const std::size_t idx : added_idx)
    d.effect_parameters.push_back(parameters_of(final_fit.comps[idx], final_sig, idx));
  d.edf_after = model_edf(d.model_after, cv, bases);
  d.after = compare(cv, model_curve(d.model_after, cv, bases), d.edf_after, alpha_tau);
}

// The verdict: the model after against its own replicas.
void Search::judge() {
  d.mc_after = opt.mc_given && d.model_after == d.model_before
                   ? d.mc_before
                   : monte_carlo(d.model_after, cv, d.after.avar_model, d.edf_after,
                                 opt.mc_replicas, opt.mc_seed, threads);
  d.gap_within_noise = within_noise(d.after.gap, d.mc_after);
}

// A model that ends beyond noise has failed the verdict's test at 1 - kGapNoiseQuantile (5 %).
// The rounds name at select_alpha / kNumEffects per candidate so that a complete model rarely gains
// an effect; one round more, at the verdict's own level and among the effects a witness attests
// (keep_witnessed), asks whether one explains the failure. Its effect is kept only if the model
// then ends within noise; otherwise the diagnosis stays as it was. On a real gyroscope (imu5 z) the
// broad pedestal beside its 17.2 Hz resonance, which leaves the model beyond noise (gap 1.36
// against 1.31), fell between the two levels.
void Search::verdict_round() {
  const Diagnosis kept = d;
  const Curve cv_kept = cv;
  const Criterion crit_kept = crit;
  const std::vector<Component> current_kept = current;
  const std::vector<std::size_t> added_kept = added_idx;
  const std::vector<Effect> removed_kept = removed;
  const bool refit_kept = refit_taken;
  const double gap = d.after.gap, p95 = d.mc_after.gap_p95;
  const double level = 1.0 - kGapNoiseQuantile;
  crit.alpha_candidate = level;
  witnessed_only = true;
  int iter = static_cast<int>(d.effects_named.size());
  bool kept_it = false;
  std::string named;
  if (round(iter)) {
    named = effect_name(d.iterations.back().effect);
    Fit base, fixed_fit;
    settle(base, fixed_fit);
    conclude(base, fixed_fit);
    judge();
    kept_it = d.gap_within_noise && d.effects_named.size() > kept.effects_named.size();
  }
  crit = crit_kept;
  witnessed_only = false;
  const std::string why = "the model ended beyond noise (gap " + std::to_string(gap) +
                          " > replicas' p95 " + std::to_string(p95) +
                          "): a round of the witnessed effects at the verdict's level (" +
                          std::to_string(level) + " per candidate) ";
  if (kept_it) {
    d.notes.push_back(why + "named " + named + ", and the model then ends within noise (gap " +
                      std::to_string(d.after.gap) + " <= " + std::to_string(d.mc_after.gap_p95) +
                      ")");
    return;
  }
  d = kept;
  cv = cv_kept;
  current = current_kept;
  added_idx = added_kept;
  removed = removed_kept;
  refit_taken = refit_kept;
  d.notes.push_back(why + (named.empty()
                               ? "named nothing (criteria: " + last_criteria + ")"
                               : "named " + named + ", not kept: the model stayed beyond noise"));
}

}  // namespace allanlot::kernels::diagnose_detail
