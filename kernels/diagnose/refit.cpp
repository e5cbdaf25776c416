// A diagnosed model's levels and shapes fitted again on the curve it is drawn against
// (docs/fit-and-psd.md "When eq. (3) is a poor fit"): diagnose names the effects and judges the
// model on its own log grid, on the record without its named jumps and with the model's edf; the
// curve drawn beside a channel's overlapping Allan deviation, and the coefficients reported with
// it, are that structure fitted on that deviation, with its taus, its jumps and its edf, with a
// hump or a resonance added where that curve asks for one by diagnose's own criterion.
#include "kernels/diagnose/internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace allanlot::kernels {

using namespace diagnose_detail;

namespace {

// The structure's shapes fitted on the curve, its free levels at each trial: the filter's form
// and value, each hump's tau_c, each resonance's f0 and q near their values.
Fit fit_shapes(std::vector<Component> comps, const Curve& cv, const Bases& raw) {
  Fit f = fit_components(std::move(comps), cv, raw);
  for (std::size_t idx = 0; idx < f.comps.size(); ++idx)
    if (is<Lowpass>(f.comps[idx])) f = search_lowpass(f.comps, idx, cv, raw);
  for (std::size_t idx = 0; idx < f.comps.size(); ++idx) {
    if (is<GaussMarkov>(f.comps[idx])) f = search_tau_c(f.comps, idx, cv, raw);
    if (is<Resonance>(f.comps[idx])) f = search_resonance(f.comps, idx, cv, raw, false);
  }
  return f;
}

// The starts of a resonance the curve may ask for: the periodogram's broad humps (diagnose's
// other starts, broad_peaks), none within a modelled resonance's half-power width (f0 / q) or
// 1/16 octave of its f0; none for a record with gaps.
std::vector<double> resonance_starts(const std::vector<Component>& comps, const Curve& cv,
                                     std::span<const double> rate, double rate_hz) {
  std::vector<double> out;
  if (rate.size() < 256 || has_nan(rate)) return out;
  const PsdResult psd = full_periodogram(rate, rate_hz, 1);
  for (const auto& peak : broad_peaks(psd, 1.0 / cv.tau.back(), kOtherStarts)) {
    const double f0 = peak.first;
    if (std::none_of(comps.begin(), comps.end(), [f0](const Component& o) {
          if (!is<Resonance>(o)) return false;
          const Resonance& r = as<Resonance>(o);
          return std::abs(f0 - r.frequency_hz) <= r.frequency_hz / r.q ||
                 std::abs(std::log2(f0 / r.frequency_hz)) <= 1.0 / 16.0;
        }))
      out.push_back(f0);
  }
  return out;
}

// Diagnose names effects on its own comparison, whose edf under a narrowband effect counts that
// effect's few independent pieces (2 B T: 34 for the ADIS16405 imu6 accel_x's 0.565 Hz resonance
// of q 1047), so that it can leave out what the drawn curve's intervals, from the measured
// curve's own edf, resolve: that channel's curve, 1-1.4 % low at 0.15-0.27 s and 2.4-4.6 % high at
// 1.3-2.4 s, needed a broad peak at 1.78 Hz (its periodogram's band there 28 % above the model)
// and a hump of tau_c 16 s beside a lower flicker floor. So the fit on the curve is offered the
// two effects the curve and the periodogram can name: a hump (hump_candidate: tau_c over its
// whole range) and a resonance from each of the periodogram's broad humps at q 8, a q at either
// end of its range no estimate, each with the structure's shapes fitted again. The one with the
// largest criterion is kept when that is positive, the criterion of diagnose's rounds: the
// chi-square's drop times n_eff / P (the curve's taus are correlated) above the chi-square
// quantile at 1 - select_alpha / kNumEffects for its 2 or 3 parameters; then the other kind once.
Fit with_curve_effects(Fit f, const Curve& cv, const Bases& raw, std::span<const double> rate,
                       double rate_hz) {
  Criterion crit;
  crit.scale = effective_taus(cv) / static_cast<double>(cv.size());
  crit.alpha_candidate = DiagnoseOptions{}.select_alpha / kNumEffects;
  const std::vector<double> starts = resonance_starts(f.comps, cv, rate, rate_hz);
  bool hump_added = false, resonance_added = false;
  for (int round = 0; round < 2; ++round) {
    Fit best;
    double best_criterion = 0.0;
    bool best_is_hump = false;
    const auto consider = [&](Fit trial, int parameters, bool hump) {
      const double c = criterion(crit, f.chi2 - trial.chi2, parameters);
      if (!(c > best_criterion)) return;
      best_criterion = c;
      best = std::move(trial);
      best_is_hump = hump;
    };
    if (!hump_added)
      if (CandidateFit h = hump_candidate(f.comps, cv, raw); !h.fit.comps.empty())
        consider(fit_shapes(std::move(h.fit.comps), cv, raw),
                 EffectTraits<GaussMarkov>::curve_parameters, true);
    const auto n_res = std::count_if(f.comps.begin(), f.comps.end(), is<Resonance>);
    for (const double f0 : starts) {
      if (resonance_added || static_cast<std::size_t>(n_res) >= EffectTraits<Resonance>::max_count)
        break;
      std::vector<Component> with = f.comps;
      with.push_back(searched_component(Resonance{0.0, f0, 8.0}));
      Fit r = fit_shapes(std::move(with), cv, raw);
      if (r.comps.back().q_bound == 0 && r.comps.back().nl_bound == 0)
        consider(std::move(r), EffectTraits<Resonance>::curve_parameters, false);
    }
    if (best.comps.empty()) break;
    (best_is_hump ? hump_added : resonance_added) = true;
    f = std::move(best);
  }
  return f;
}

}  // namespace

ChannelSpec fit_to_curve(const ChannelSpec& model, const StatResult& oadev, std::int64_t n_samples,
                         std::span<const double> rate) {
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
  const Fit f =
      with_curve_effects(fit_shapes(std::move(comps), cv, raw), cv, raw, rate, model.rate_hz);
  return spec_of(f.comps, model);
}

}  // namespace allanlot::kernels
