// The sensor's filter named from a measured Allan curve alone, for analyze's eq. (3) fit
// (docs/fit-and-psd.md "The sensor's filter"): diagnose's own lowpass candidate and criterion
// (candidates.cpp, docs/diagnose.md "The sensor's filter"), so that analyze and diagnose name the
// same filter from the same facts.
#include "kernels/diagnose/internal.hpp"

#include "kernels/model/units.hpp"

#include <stdexcept>
#include <string>

namespace allanlot::kernels {

using namespace diagnose_detail;

LowpassFinding find_lowpass(const StatResult& oadev, double rate_hz, std::int64_t n_samples,
                            double n_eff, double select_alpha) {
  if (!(rate_hz > 0.0) || n_samples < 1)
    throw std::invalid_argument("find_lowpass: rate_hz and n_samples must be positive");
  LowpassFinding out;
  Curve cv = curve_of(oadev, rate_hz, n_samples);
  // Five free terms and the filter: fewer taus leave nothing to judge the filter by.
  if (cv.size() < 7) return out;
  if (!(n_eff > 0.0)) n_eff = effective_taus(cv);
  const Bases bases = make_bases(cv, rate_hz);
  // The reference: the five terms of eq. (3) re-estimated with no filter, its fit weighted and
  // judged with the edf of that model (diagnose's rule: the hypothesis under test sets the edf).
  std::vector<Component> terms;
  for (const Term t : all_terms()) {
    terms.push_back(component(TermLevel{t}));
    terms.back().free = true;
  }
  ChannelSpec like;
  like.rate_hz = rate_hz;
  Fit ref = fit_components(terms, cv, bases);
  use_edf(cv, model_edf(spec_of(ref.comps, like), cv, bases));
  ref = fit_components(ref.comps, cv, bases);
  Criterion crit;
  crit.n_eff = n_eff;
  crit.rate_hz = rate_hz;
  crit.scale = n_eff / static_cast<double>(cv.size());
  crit.alpha_candidate = select_alpha / kNumEffects;
  const CandidateFit cf =
      evaluate_candidate(Effect::Lowpass, ref.comps, Witnesses{}, 0, ref.chi2, cv, bases, crit);
  if (!cf.info.evaluated) return out;
  out.delta_ic = cf.info.delta_ic;
  if (out.delta_ic > 0.0) out.filter = as<Lowpass>(cf.fit.comps[cf.added]);
  return out;
}

}  // namespace allanlot::kernels
