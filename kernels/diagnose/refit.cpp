// A diagnosed model's levels and shapes fitted again on the curve it is drawn against
// (docs/fit-and-psd.md "When eq. (3) is a poor fit"): diagnose names the effects and judges the
// model on its own log grid, on the record without its named jumps and with the model's edf; the
// curve drawn beside a channel's overlapping Allan deviation, and the coefficients reported with
// it, are that structure fitted on that deviation, with its taus, its jumps and its edf.
#include "kernels/diagnose/internal.hpp"

#include <cstddef>
#include <cstdint>

namespace allanlot::kernels {

using namespace diagnose_detail;

ChannelSpec fit_to_curve(const ChannelSpec& model, const StatResult& oadev,
                         std::int64_t n_samples) {
  validate(model);
  Curve cv = curve_of(oadev, model.rate_hz, n_samples);
  if (cv.size() < 4) return model;
  // The jumps are in the record the deviation was measured on: their share of each tau
  // (step_avar_sampled) is known, as the rounding's is, and fitted as neither.
  Bases raw = make_bases(cv, model.rate_hz, model.quantum);
  for (std::size_t i = 0; i < cv.size(); ++i)
    if (2 * cv.m[i] <= n_samples)
      raw.fixed[i] = plus_steps_avar(raw.fixed[i], model.steps, model.rate_hz, cv.m[i], n_samples);
  std::vector<Component> comps = components_of(model);
  // Every noise term of eq. (3) may take a level (the ramp only when the model has one: its
  // witness is the record's slope, not the curve).
  for (const Term t : {Term::Q, Term::N, Term::B, Term::K})
    if (!(coefficient(model.terms, t) > 0.0)) comps.push_back(component(TermLevel{t}));
  // Levels free; a line's amplitude stays its PSD's (its bump on the curve overlaps any hump
  // beside it), a jump its record's, a filter is a shape.
  for (Component& c : comps) {
    c.nl_free = is<GaussMarkov>(c) || is<Resonance>(c);
    c.free = is<TermLevel>(c) || c.nl_free;
  }
  Fit f = fit_components(comps, cv, raw);
  for (std::size_t idx = 0; idx < f.comps.size(); ++idx)
    if (is<Lowpass>(f.comps[idx])) f = search_lowpass(f.comps, idx, cv, raw);
  for (std::size_t idx = 0; idx < f.comps.size(); ++idx) {
    if (is<GaussMarkov>(f.comps[idx])) f = search_tau_c(f.comps, idx, cv, raw);
    if (is<Resonance>(f.comps[idx])) f = search_resonance(f.comps, idx, cv, raw, false);
  }
  return spec_of(f.comps, model);
}

}  // namespace allanlot::kernels
