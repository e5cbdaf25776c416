// A round's candidates (docs/diagnose.md "Why"): each effect added to the model as it stands,
// fitted, and judged by the round's criterion. Each effect proposes itself its own way (a term
// is a free level, a line and a jump come from their witnesses, a filter, a hump and a resonance
// are searched on the curve); the switch below covers every Effect, so an effect without its
// proposal does not compile.
#include "kernels/diagnose/internal.hpp"

#include "kernels/uncertainty/chi2.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace allanlot::kernels::diagnose_detail {
namespace {

// A candidate before it is judged: the fit with the effect added (no components and a note when
// it cannot be added), the parameters the curve charges for it beyond the refit's and the curve
// it was fitted on (the record without a witnessed jump for a step).
struct Proposal {
  CandidateFit cf;
  int k = 0;
  const Curve* on = nullptr;
};

Proposal term_proposal(Term t, std::vector<Component> comps, const Curve& cv, const Bases& b) {
  Proposal p{{}, 1, &cv};
  if (std::any_of(comps.begin(), comps.end(), [&](const auto& c) { return is_term(c, t); })) {
    p.cf.info.note = "already in the model";
    return p;
  }
  comps.push_back(component(TermLevel{t}));
  comps.back().free = true;
  p.cf.fit = fit_components(std::move(comps), cv, b);
  return p;
}

// No penalty: the line's frequency and amplitude come from its witness, not from the Allan
// curve, and the witness has its own false-alarm level (line_false_alarm per record). The curve
// is asked only whether the line is part of what it measures (its chi-square falls). Charging
// its two parameters again at select_alpha / 9 missed lines that the periodogram saw at 1e-4
// (weak level of the study: 2 of 10 named, docs/diagnose.md).
Proposal line_proposal(std::vector<Component> comps, const SpectralLine& line, const Curve& cv,
                       const Bases& b, double rate_hz) {
  Proposal p{{}, EffectTraits<Sinusoid>::curve_parameters, &cv};
  std::string& note = p.cf.info.note;
  if (!line.searched) {
    note = "no PSD witness (gaps or short record)";
    return p;
  }
  if (!line.found || line.frequency_hz > 0.5 * rate_hz) {
    note = "the PSD shows no line (peak/background " + std::to_string(line.peak_ratio) +
           " < threshold " + std::to_string(line.threshold) + ")";
    if (line.wide_hz > 0.0)
      note += "; its peak at " + std::to_string(line.wide_hz) +
              " Hz is wider than a line (a narrowband process)";
    return p;
  }
  Component c = component(Sinusoid{line.amplitude, line.frequency_hz});
  c.nl_sigma = line.sigma_hz;
  c.coef_sigma = line.amplitude_sigma;
  c.pinned = true;
  comps.push_back(c);
  p.cf.fit = fit_components(std::move(comps), cv, b);
  note = "PSD line at " + std::to_string(line.frequency_hz) + " Hz, peak/background " +
         std::to_string(line.peak_ratio);
  return p;
}

// The model as it stands fitted to the record without the jump; no penalty, as for a line: size
// and time come from the witness (step_false_alarm).
Proposal jump_proposal(std::vector<Component> comps, const Witnesses& seen, const Bases& b) {
  Proposal p{{}, EffectTraits<Step>::curve_parameters, seen.without_jump};
  const StepWitness& jump = seen.step;
  std::string& note = p.cf.info.note;
  if (!jump.searched) {
    note = "no time-domain witness (gaps or short record)";
    return p;
  }
  if (!jump.found) {
    note = jump.note.empty() ? "the record shows no jump (p = " + std::to_string(jump.p_value) +
                                   " >= " + std::to_string(jump.false_alarm) + ")"
                             : jump.note;
    return p;
  }
  if (seen.without_jump == nullptr) {
    note = "the record without the jump has another tau grid";
    return p;
  }
  Component c = step_component({jump.size, jump.time_s});
  c.nl_sigma = jump.time_sigma_s;
  c.coef_sigma = jump.size_sigma;
  comps.push_back(c);
  p.cf.fit = fit_components(std::move(comps), *seen.without_jump, b);
  note = "jump of " + std::to_string(jump.size) + " at " + std::to_string(jump.time_s) +
         " s, p = " + std::to_string(jump.p_value);
  return p;
}

Proposal filter_proposal(std::vector<Component> comps, const Curve& cv, const Bases& b) {
  Proposal p{{}, EffectTraits<Lowpass>::curve_parameters, &cv};
  if (lowpass_of(comps).active())
    p.cf.info.note = "already in the model";
  else
    p.cf = lowpass_candidate(std::move(comps), cv, b);
  return p;
}

// A resonance its witness, a PSD peak wider than a line, measured (f0, q and sigma: no penalty,
// as for a witnessed line), else one searched on the curve and shaped on the periodogram.
Proposal resonance_proposal(std::vector<Component> comps, const Witnesses& seen, const Curve& cv,
                            const Bases& b, const Criterion& crit) {
  Proposal p{{}, 0, &cv};
  if (seen.line.narrowband.found) {
    p.cf = witnessed_resonance(std::move(comps), seen.line.narrowband, cv, b);
    return p;
  }
  p.cf = resonance_candidate(std::move(comps), cv, b, seen, [&](int n) {
    return threshold(n, crit.alpha_candidate) / crit.scale;
  });
  if (!p.cf.fit.comps.empty()) p.k = resonance_parameters(p.cf.fit.comps.back());
  return p;
}

Proposal propose(Effect e, std::vector<Component> comps, const Witnesses& seen, const Curve& cv,
                 const Bases& b, const Criterion& crit) {
  switch (e) {
  case Effect::Quantization:
  case Effect::White:
  case Effect::Flicker:
  case Effect::RandomWalk:
  case Effect::Ramp:
    return term_proposal(*effect_term(e), std::move(comps), cv, b);
  case Effect::Sinusoid:
    return line_proposal(std::move(comps), seen.line, cv, b, crit.rate_hz);
  case Effect::Step:
    return jump_proposal(std::move(comps), seen, b);
  case Effect::Lowpass:
    return filter_proposal(std::move(comps), cv, b);
  case Effect::Markov:
    return {hump_candidate(std::move(comps), cv, b), EffectTraits<GaussMarkov>::curve_parameters,
            &cv};
  case Effect::Resonance:
    return resonance_proposal(std::move(comps), seen, cv, b, crit);
  }
  return {};
}

}  // namespace

CandidateFit evaluate_candidate(Effect e, std::vector<Component> comps, const Witnesses& seen,
                                int n_refit, double chi2_ref, const Curve& cv, const Bases& b,
                                const Criterion& crit) {
  Proposal p = propose(e, std::move(comps), seen, cv, b, crit);
  p.cf.info.effect = e;
  if (p.cf.fit.comps.empty()) return std::move(p.cf);
  score_candidate(p.cf, n_refit + p.k, chi2_ref, *p.on, b, crit);
  return std::move(p.cf);
}

// The curve's parameters of a resonance: f0, q and sigma searched on it, or sigma alone where the
// periodogram measured the shape (psd_shape): the shape then has its witness and that witness's
// false alarm (fit_peak_shapes' likelihood ratio at line_false_alarm), as a witnessed line has.
int resonance_parameters(const Component& c) {
  return c.psd_shape ? 1 : EffectTraits<Resonance>::curve_parameters;
}

void score_candidate(CandidateFit& cf, int k, double chi2_ref, const Curve& fit_cv, const Bases& b,
                     const Criterion& crit) {
  cf.added = cf.fit.comps.size() - 1;
  cf.info.evaluated = true;
  cf.info.delta_ic = criterion(crit, chi2_ref - cf.fit.chi2, k);
  cf.info.parameters =
      parameters_of(cf.fit.comps[cf.added], fill_sigmas(cf.fit, fit_cv, b, crit.n_eff), cf.added);
}

}  // namespace allanlot::kernels::diagnose_detail
