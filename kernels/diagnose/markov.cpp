// Diagnose's Gauss-Markov hump (docs/diagnose.md "Why"): its Allan curve under the sensor's
// filter, the search of its correlation time on the measured curve, and its candidate.
#include "kernels/diagnose/internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>

namespace allanlot::kernels::diagnose_detail {
namespace {

// Markov candidate: a new component, its tau_c searched with the others' coefficients as
// `base` has them (fixed or free).
CandidateFit markov_candidate(std::vector<Component> base, const Curve& cv, const Bases& b) {
  base.push_back(searched_component(GaussMarkov{}));
  const std::size_t idx = base.size() - 1;
  CandidateFit out;
  out.fit = search_tau_c(std::move(base), idx, cv, b);
  out.added = out.fit.comps.size() - 1;
  return out;
}

}  // namespace

// The Allan variance of a Gauss-Markov effect at the curve's taus under the filter `lp`, as
// model_avar_sampled has it; unfiltered, model_avar's continuous form (the same values).
std::vector<double> markov_curve(double sigma, double tau_c_s, const Curve& cv, const Lowpass& lp,
                                 double rate_hz) {
  std::vector<double> g(cv.size());
  if (!lp.active()) {
    ChannelSpec s;
    s.rate_hz = rate_hz;
    s.markovs.push_back({sigma, tau_c_s});
    for (std::size_t i = 0; i < cv.size(); ++i)
      g[i] = model_avar(s, cv.tau[i]);
    return g;
  }
  const std::vector<double> rho = lowpass_autocorrelation(lp, rate_hz);
  for (std::size_t i = 0; i < cv.size(); ++i)
    g[i] = lowpass_markov_avar(sigma, tau_c_s, rate_hz, cv.m[i], rho);
  return g;
}

// tau_c of the Markov component comps[idx] by a log grid of 8 per octave from one sample to
// the record's length (the range must not end inside the taus, where a pinned tau_c would
// absorb ramps and sensor filtering), then golden-section search on ln tau_c between the
// neighbours of the best grid point; the free coefficients are fitted at each tau_c. A best
// point within one grid step of either end is marked as a bound (Component::nl_bound).
Fit search_tau_c(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b) {
  const auto eval = [&](double tau_c) {
    as<GaussMarkov>(comps[idx]).tau_c_s = tau_c;
    return fit_components(comps, cv, b);
  };
  const double lo = std::log(cv.tau0), hi = std::log(static_cast<double>(cv.n_samples) * cv.tau0);
  const int n_grid = static_cast<int>(std::ceil((hi - lo) / (std::numbers::ln2 / 8.0))) + 1;
  const double step = (hi - lo) / (n_grid - 1);
  double best_chi2 = std::numeric_limits<double>::infinity();
  int best = 0;
  for (int g = 0; g < n_grid; ++g) {
    const Fit f = eval(std::exp(lo + step * g));
    if (f.chi2 < best_chi2) {
      best_chi2 = f.chi2;
      best = g;
    }
  }
  const double x =
      golden_min([&](double v) { return eval(std::exp(v)).chi2; },
                 lo + step * std::max(best - 1, 0), lo + step * std::min(best + 1, n_grid - 1));
  Fit grid_best = eval(std::exp(lo + step * best));
  Fit refined = eval(std::exp(x));
  Fit& out = refined.chi2 <= grid_best.chi2 ? refined : grid_best;
  const double x_out = std::log(as<GaussMarkov>(out.comps[idx]).tau_c_s);
  out.comps[idx].nl_bound = x_out < lo + step ? -1 : x_out > lo + step * (n_grid - 2) ? 1 : 0;
  return out;
}

// Markov candidate with its refusals (no fit, a note): the simulator's limit on humps, a hump
// within a decade of another, and one whose tau_c ends at one sample.
CandidateFit hump_candidate(std::vector<Component> comps, const Curve& cv, const Bases& b) {
  const auto n_markov = std::count_if(comps.begin(), comps.end(), is<GaussMarkov>);
  if (static_cast<std::size_t>(n_markov) >= EffectTraits<GaussMarkov>::max_count) {
    CandidateFit none;
    none.info.effect = Effect::Markov;
    none.info.note = "too many markov effects";
    return none;
  }
  CandidateFit cf = markov_candidate(std::move(comps), cv, b);
  cf.info.effect = Effect::Markov;
  // A second Gauss-Markov effect is a distinct instance only a decade or more from every
  // other: closer, two humps are one hump re-split.
  const double tc = as<GaussMarkov>(cf.fit.comps.back()).tau_c_s;
  for (std::size_t i = 0; i + 1 < cf.fit.comps.size(); ++i)
    if (is<GaussMarkov>(cf.fit.comps[i]) &&
        std::abs(std::log10(tc / as<GaussMarkov>(cf.fit.comps[i]).tau_c_s)) < 1.0) {
      CandidateFit none;
      none.info.effect = Effect::Markov;
      none.info.note = "its tau_c " + std::to_string(tc) + " s is within a decade of " +
                       component_label(cf.fit.comps, i) + "'s";
      return none;
    }
  // A tau_c at the bottom of its range, one sample, is no hump: white noise with a shape at
  // the shortest taus, which is the sensor's filter's (such humps would stand in for the
  // filter; an ADIS16405 z gyroscope's scores 2127 against the filter's 2108).
  if (cf.fit.comps.back().nl_bound < 0) {
    CandidateFit none;
    none.info.effect = Effect::Markov;
    none.info.note = "its tau_c is at one sample, the bottom of its range: a shape at the "
                     "shortest taus (a filter's), not a hump";
    return none;
  }
  return cf;
}

}  // namespace allanlot::kernels::diagnose_detail
