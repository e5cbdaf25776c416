#include "src/pipeline/channel_model.hpp"

#include "kernels/diagnose/diagnose.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/model/units.hpp"
#include "kernels/simulate/simulate.hpp"
#include "src/pipeline/channel_fit.hpp"
#include "src/pipeline/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace allanlot::pipeline {
namespace {

using kernels::units::Term;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The eq. (3) fit's detection rule and 95 % upper bound (kernels/model/fit.hpp FitOptions:
// theta > 2 sigma(theta), with sigma(theta) = 2 value sigma(value) to first order; the one-sided
// normal quantile 1.645), applied to the model's coefficients.
constexpr double kDetectionSigmas = 2.0;
constexpr double kUpperZ = 1.6448536269514722;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The step of the output word when every sample lies on one (the ADIS16405's accelerometers:
// 0.00333 g, against a sample standard deviation of 1.2 steps), 0 otherwise. The sensor rounds
// after its filter, so its rounding adds unfiltered white noise of quantum^2 / 12 a sample
// (kernels::ChannelSpec::quantum) beside the filtered white noise: about 6 % of an accelerometer's
// variance at tau0, whose shortest taus eq. (3) plus a filter alone then miss by 1-4 %. The step
// is the smallest gap between distinct values of the first 2^16 samples (values within 1e-6 of
// the largest magnitude are one: `rate` is rebuilt from the phase, whose sums round), accepted
// when every sample lies within 1e-3 steps of the lattice and the record's standard deviation is
// a step or more (where the rounding error is white and uniform: kernels/simulate/simulate.hpp).
double output_quantum(std::span<const double> rate) {
  if (rate.size() < 3) return 0.0;
  std::vector<double> v(
      rate.begin(), rate.begin() + static_cast<std::ptrdiff_t>(
                                       std::min<std::size_t>(rate.size(), std::size_t{1} << 16)));
  std::sort(v.begin(), v.end());
  if (!std::isfinite(v.front()) || !std::isfinite(v.back())) return 0.0;
  const double tol = 1e-6 * std::max(std::abs(v.front()), std::abs(v.back()));
  double q = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < v.size(); ++i)
    if (v[i] - v[i - 1] > tol) q = std::min(q, v[i] - v[i - 1]);
  if (!std::isfinite(q) || !(q > 4.0 * tol)) return 0.0;
  const double x0 = v.front();
  double sum = 0.0, sum_sq = 0.0;
  for (const double y : rate) {
    const double k = (y - x0) / q;
    if (!(std::abs(k - std::nearbyint(k)) <= 1e-3)) return 0.0;
    sum += k;
    sum_sq += k * k;
  }
  const auto n = static_cast<double>(rate.size());
  const double var_steps = sum_sq / n - (sum / n) * (sum / n);
  return var_steps >= 1.0 ? q : 0.0;
}

// The eq. (3) fit over every tau as diagnose's given model (`all_taus`: its terms in channel
// units, as the study of docs/diagnose.md "Real sensors" gives them), and the filter when
// --lowpass gave it (`fit`). The fit from a filter's first tau on is no start: where an effect
// dominates its taus it can lose a term the short taus measure (white noise under a 0.25 Hz
// resonance fitted from 2 s). A filter the fit found on the curve is left for diagnose to name: a
// given filter is kept as it is, and the fit's test, made without the effects, can choose the wrong
// form (the ADIS16405 imu2 accel_z's 18.5 Hz first order, given, left its model at gap 3.8
// against a p95 of 1.3; named by diagnose, 1.14 taps and within noise).
kernels::ChannelSpec given_model(const io::FitRecord& fit, const io::FitRecord& all_taus,
                                 double rate_hz, double quantum) {
  kernels::ChannelSpec spec;
  spec.rate_hz = rate_hz;
  spec.quantum = quantum;
  // The fit over every tau can fail to converge where a filter's deficit dominates the short
  // taus: then the fit reported is the start.
  for (const io::TermRecord& t : kernels::has_terms(all_taus.status) ? all_taus.terms : fit.terms)
    if (const auto term = kernels::units::parse_term(t.term))
      kernels::coefficient(spec.terms, *term) = t.value;
  if (fit.lowpass == "option") {
    if (std::isfinite(fit.lowpass_cutoff_hz)) spec.lowpass.cutoff_hz = fit.lowpass_cutoff_hz;
    if (std::isfinite(fit.lowpass_taps)) spec.lowpass.taps = fit.lowpass_taps;
  }
  return spec;
}

// The value of parameter `name` of the k-th hump, resonance or filter of the drawn model (what
// kernels::fit_to_curve fitted again); `value` for any other (a line's, a jump's, a term's).
double drawn_value(const kernels::ChannelSpec& drawn, kernels::Effect e, std::size_t k,
                   const std::string& name, double value) {
  using kernels::Effect;
  if (e == Effect::Lowpass) return name == "taps" ? drawn.lowpass.taps : drawn.lowpass.cutoff_hz;
  if (e == Effect::Markov && k < drawn.markovs.size())
    return name == "sigma" ? drawn.markovs[k].sigma : drawn.markovs[k].tau_c_s;
  if (e == Effect::Resonance && k < drawn.resonances.size()) {
    const kernels::Resonance& r = drawn.resonances[k];
    if (name == "sigma") return r.sigma;
    if (name == "frequency_hz") return r.frequency_hz;
    if (name == "q") return r.q;
  }
  return value;
}

// "eq. (3) + rounding 0.00333 g, lowpass 1.15 taps, resonance 17.2 Hz, markov 257 s, step at
// 42.3 s": the output's rounding when the record shows one, then the effects outside eq. (3) in
// the order named (a term named is eq. (3)'s own), the filter first when it was given rather
// than named, then those the fit on the curve added (kernels::fit_to_curve), resonances first.
std::string describe(const kernels::Diagnosis& d, const kernels::ChannelSpec& drawn,
                     const std::string& units) {
  std::vector<std::string> parts;
  if (drawn.quantum > 0) parts.push_back("rounding " + num(drawn.quantum) + " " + units);
  const kernels::Lowpass& lp = drawn.lowpass;
  const auto filter = [&lp] {
    return "lowpass " + (lp.taps > 0 ? num(lp.taps) + " taps" : num(lp.cutoff_hz) + " Hz");
  };
  const bool named_filter = std::find(d.effects_named.begin(), d.effects_named.end(),
                                      kernels::Effect::Lowpass) != d.effects_named.end();
  if (lp.active() && !named_filter) parts.push_back(filter());
  std::vector<std::size_t> seen(kernels::kNumEffects, 0);
  for (std::size_t i = 0; i < d.effects_named.size(); ++i) {
    const kernels::Effect e = d.effects_named[i];
    const std::size_t k = seen[static_cast<std::size_t>(e)]++;
    const auto value = [&](const char* name) {
      double v = kNaN;
      for (const auto& p : d.effect_parameters[i])
        if (p.name == name) v = p.value;
      return drawn_value(drawn, e, k, name, v);
    };
    switch (e) {
    case kernels::Effect::Lowpass:
      parts.push_back(filter());
      break;
    case kernels::Effect::Resonance:
      parts.push_back("resonance " + num(value("frequency_hz")) + " Hz");
      break;
    case kernels::Effect::Sinusoid:
      parts.push_back("sinusoid " + num(value("frequency_hz")) + " Hz");
      break;
    case kernels::Effect::Markov:
      parts.push_back("markov " + num(value("tau_c_s")) + " s");
      break;
    case kernels::Effect::Step:
      parts.push_back("step at " + num(value("time_s")) + " s");
      break;
    default:
      break;  // a term of eq. (3)
    }
  }
  for (std::size_t k = d.model_after.resonances.size(); k < drawn.resonances.size(); ++k)
    parts.push_back("resonance " + num(drawn.resonances[k].frequency_hz) + " Hz");
  for (std::size_t k = d.model_after.markovs.size(); k < drawn.markovs.size(); ++k)
    parts.push_back("markov " + num(drawn.markovs[k].tau_c_s) + " s");
  std::string s = "eq. (3)";
  for (std::size_t i = 0; i < parts.size(); ++i)
    s += (i == 0 ? " + " : ", ") + parts[i];
  return s;
}

// The 1-sigma of term t in the corrected model: the given coefficient's, re-estimated with
// every effect in place (Diagnosis::revisions), or the term's own when diagnose named it as an
// effect; NaN when neither (the term is not in the model).
double term_sigma(const kernels::Diagnosis& d, Term t) {
  const std::string name(kernels::units::term_name(t));
  for (const auto& r : d.revisions)
    if (r.name == name) return r.sigma;
  for (std::size_t i = 0; i < d.effects_named.size(); ++i)
    if (kernels::effect_term(d.effects_named[i]) == t)
      for (const auto& p : d.effect_parameters[i])
        if (p.name == name) return p.sigma;
  return kNaN;
}

// fit/'s term table from the corrected model. A term the model holds at zero (or whose sigma
// is not estimable) keeps the eq. (3) fit's 95 % upper bound: eq. (3) alone gives the term
// every part of the curve the effects explain, so its bound is conservative for the model.
std::vector<io::TermRecord> model_terms(const kernels::Diagnosis& d,
                                        const kernels::ChannelSpec& drawn, const io::FitRecord& eq3,
                                        const std::string& units) {
  std::vector<io::TermRecord> out;
  for (const Term t : kernels::units::all_terms()) {
    const io::TermRecord* old = nullptr;
    for (const auto& r : eq3.terms)
      if (r.term == kernels::units::term_name(t)) old = &r;
    kernels::TermFit f;
    f.value = kernels::coefficient(drawn.terms, t);
    f.sigma = term_sigma(d, t);
    if (!std::isfinite(f.sigma) && old && f.value == old->value) f.sigma = old->sigma;
    f.detected = std::isfinite(f.sigma) && f.value > 2.0 * kDetectionSigmas * f.sigma;
    f.upper = std::isfinite(f.sigma) ? f.value + kUpperZ * f.sigma : kNaN;
    if (!f.detected && old)
      f.upper = std::isfinite(f.upper) ? std::max(f.upper, old->upper) : old->upper;
    if (!std::isfinite(f.sigma)) f.sigma = old ? old->sigma : kNaN;
    out.push_back(term_record(t, f, units));
  }
  return out;
}

// The named effects with the drawn model's values (diagnose's sigmas and bounds): the k-th
// effect of a kind named is the k-th of that kind in the model, as diagnose adds them in turn.
std::vector<io::EffectRecord> effect_records(const kernels::Diagnosis& d,
                                             const kernels::ChannelSpec& drawn) {
  std::vector<io::EffectRecord> out;
  std::vector<std::size_t> seen(kernels::kNumEffects, 0);
  for (std::size_t i = 0; i < d.effects_named.size(); ++i) {
    const kernels::Effect e = d.effects_named[i];
    const std::size_t k = seen[static_cast<std::size_t>(e)]++;
    for (const auto& p : d.effect_parameters[i])
      out.push_back({static_cast<std::int64_t>(i), std::string(kernels::effect_name(e)), p.name,
                     drawn_value(drawn, e, k, p.name, p.value), p.sigma, p.bound});
  }
  // The effects the fit on the curve added, after diagnose's, in describe's order, under their
  // model-file keys; the curve's fit estimates no sigma.
  auto index = static_cast<std::int64_t>(d.effects_named.size());
  const auto added = [&](const auto& list, std::size_t first) {
    using E = typename std::decay_t<decltype(list)>::value_type;
    for (std::size_t i = first; i < list.size(); ++i, ++index)
      for (const auto& k : kernels::EffectTraits<E>::keys)
        if (kernels::written(k, list[i]))
          out.push_back({index, std::string(kernels::EffectTraits<E>::name), std::string(k.name),
                         list[i].*k.field, kNaN, 0});
  };
  added(drawn.resonances, d.model_after.resonances.size());
  added(drawn.markovs, d.model_after.markovs.size());
  return out;
}

// The read-outs' `model` and validity under the corrected model, as fit_channel computes them
// under eq. (3) (N at 1 s; the minimum over 2 ln2 / pi; the lowest +1/2 line at 3 s), on the
// drawn curve's taus.
void model_readouts(io::FitRecord& fit, const kernels::ChannelSpec& model) {
  double min_avar = std::numeric_limits<double>::infinity(), min_k = min_avar;
  for (std::size_t i = 0; i < fit.tau.size(); ++i) {
    const double avar = fit.adev_model[i] * fit.adev_model[i];
    min_avar = std::min(min_avar, avar);
    min_k = std::min(min_k, avar / fit.tau[i]);
  }
  const double floor = kernels::eq3_regressors(1.0)[static_cast<std::size_t>(Term::B)];
  const auto detected = [&fit](const char* term) {
    for (const auto& t : fit.terms)
      if (t.term == term) return t.detected;
    return false;
  };
  for (io::ReadoutRecord& r : fit.readouts) {
    if (r.name == "N_1s") {
      r.model = std::sqrt(kernels::model_avar(model, 1.0));
      r.valid = r.value > 0.0 && detected("N");
    } else if (r.name == "bias_instability") {
      r.model = std::sqrt(min_avar / floor);
      r.valid = detected("B");
    } else if (r.name == "K_3s") {
      r.model = std::sqrt(3.0 * min_k);
      r.valid = detected("K");
    }
  }
}

}  // namespace

void model_poor_fit(io::ChannelResult& result, const kernels::PhaseData& phase,
                    const kernels::StatResult& oadev, const ModelChoice& choice, int threads) {
  if (!choice.enabled || !result.fit || result.fit->status != kernels::FitStatus::PoorFit) return;
  io::FitRecord& fit = *result.fit;
  const double rate_hz = 1.0 / phase.tau0_s;
  const kernels::LargeVector<double> rate = rate_from_phase(phase);
  kernels::DiagnoseOptions opt;
  opt.mc_replicas = choice.replicas;
  opt.mc_seed = choice.seed;
  opt.nthreads = threads;
  opt.mc_given = false;  // the given model's replicas: analyze reports only the corrected model's
  kernels::Diagnosis d;
  kernels::ChannelSpec drawn;
  const auto n = static_cast<std::int64_t>(rate.size());
  try {
    const LowpassChoice none{LowpassChoice::Mode::None, {}};
    const io::FitRecord all_taus = fit_channel(oadev, phase.tau0_s, phase.n_points() - 1,
                                               result.units, none, nullptr, threads);
    d = kernels::diagnose(rate, rate_hz, given_model(fit, all_taus, rate_hz, output_quantum(rate)),
                          opt);
    // The structure diagnose named, its levels and shapes fitted on the deviation it is drawn
    // against (kernels::fit_to_curve): diagnose's fit is on its own grid, without the record's
    // jumps and with the model's edf, and missed the ADIS16405 accelerometers' curves by 1-2 %
    // at taus whose intervals are 0.3-1 % wide, and by 1.2-1.7 times at the longest taus. The
    // record's samples give the fit its periodogram, whose broad humps start a resonance the
    // curve asks for.
    drawn = kernels::fit_to_curve(d.model_after, oadev, n, rate);
  } catch (const std::exception& e) {
    // The eq. (3) fit stands, with the reason: a model that cannot be made fails no channel.
    result.notes +=
        (result.notes.empty() ? "" : "; ") + std::string("poor fit not modelled: ") + e.what();
    return;
  }
  fit.adev_model.clear();
  for (const std::int64_t m : oadev.m)
    fit.adev_model.push_back(std::sqrt(kernels::model_avar_sampled(drawn, m, 2 * m <= n ? n : 0)));
  fit.terms = model_terms(d, drawn, fit, result.units);
  fit.model = describe(d, drawn, result.units);
  fit.model_gap = d.after.gap;
  fit.model_gap_p95 = d.mc_after.gap_p95;
  fit.model_replicas = d.mc_after.replicas;
  fit.model_within_noise = d.gap_within_noise ? 1 : 0;
  fit.effects = effect_records(d, drawn);
  model_readouts(fit, drawn);
}

}  // namespace allanlot::pipeline
