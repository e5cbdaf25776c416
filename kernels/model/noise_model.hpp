// The noise model: one value type for everything a channel's noise is, read by simulate,
// diagnose, the model file, the command line and Python alike.
//
//   y_k = offset + the five eq. (3) terms (terms.hpp) + flicker PM + the sum of the effects,
//
// all of it passed through the sensor's filter (`lowpass`) and rounded to the output word
// (`quantum`); kernels/simulate/simulate.hpp says how each part is synthesized and what its
// Allan variance is.
//
// The effects outside eq. (3) are registered in kEffectLists below, one line each; each has its
// own header in kernels/model/effects/ with everything about it (its struct, its name and
// model-file keys, its checks, the most a channel holds, the parameters diagnose fits; its Allan
// variance and PSD where they are closed forms), and its process file in kernels/simulate/ (its
// synthesis, random streams and shares of the model's Allan variance and PSD). Code that treats
// every effect alike (the model file's reader and writer, the copy of a diagnosed model,
// simulate) iterates kEffectLists with for_each_effect_list and reads EffectTraits, so a new
// effect is its header, its process file and its line here (docs/development.md "How to add an
// effect").
#pragma once

#include "kernels/model/effects/lowpass.hpp"
#include "kernels/model/effects/markov.hpp"
#include "kernels/model/effects/resonance.hpp"
#include "kernels/model/effects/sinusoid.hpp"
#include "kernels/model/effects/step.hpp"
#include "kernels/model/terms.hpp"

#include <string>
#include <tuple>
#include <vector>

namespace allanlot::kernels {

/// Everything that defines one channel's noise (kernels::ChannelSpec to simulate it).
struct NoiseModel {
  double rate_hz = 1;                 // sample rate; tau0 = 1 / rate_hz
  NoiseTerms terms;                   // eq. (3) coefficients
  std::vector<Sinusoid> sinusoids;    // effects outside eq. (3), in the order given
  std::vector<GaussMarkov> markovs;   // at most EffectTraits<GaussMarkov>::max_count
  std::vector<Resonance> resonances;  // narrowband noises, at most its max_count
  std::vector<Step> steps;            // bias jumps, in any order
  double offset = 0;                  // constant added to every sample [u] (e.g. 1 g)
  Lowpass lowpass;                    // the sensor's filter, applied to the sum (none by default)
  // The step of the output word [u] (0: none). A sensor quantizes after its filter: its rounding
  // error is white, of variance quantum^2 / 12 (uniform on one step), and unfiltered. That holds
  // when the rounded signal's standard deviation is a step or more (Widrow & Kollar,
  // "Quantization Noise", 2008, ch. 4: the characteristic function at 2 pi / quantum is then
  // below 3e-9), so simulate_channel rounds the filtered sum to whole steps and model_avar adds
  // quantum^2 / (12 m) at tau = m / rate_hz.
  double quantum = 0;
  // Flicker PM, a clock's noise type that eq. (3) lacks: the level h_1 of the rate's one-sided
  // PSD S(f) = h_1 f [u^2/Hz^2] (docs/clocks.md). Synthesized as Kasdin's flicker sequence on
  // the phase (S_x = h_1 / (4 pi^2 f), so the driving variance is h_1 / (4 pi)), differenced
  // to the rate with the phase before the record zero; its Allan variance is SP1065's
  // [1.038 + 3 ln(2 pi f_h tau)] h_1 / (4 pi^2 tau^2) (kernels/powerlaw/theory.hpp), which
  // model_avar uses, within 10 % from m = 4 on (17 % above it at m = 1: the discrete
  // sequence's power near Nyquist; tests/kernels/test_powerlaw_fit.cpp).
  double flicker_pm = 0;
  friend bool operator==(const NoiseModel&, const NoiseModel&) = default;
};

/// The registered effects that a channel holds a list of, in the order the model file writes
/// them (the filter, at most one, follows them): one line per effect.
inline constexpr auto kEffectLists = std::make_tuple(  //
    &NoiseModel::sinusoids,                            //
    &NoiseModel::markovs,                              //
    &NoiseModel::resonances,                           //
    &NoiseModel::steps);

/// Calls f(list) for each registered effect list of m, in kEffectLists order; f is generic over
/// std::vector<E>, E's facts in EffectTraits<E>.
template <class Model, class F>
void for_each_effect_list(Model& m, F&& f) {
  std::apply([&](auto... list) { (f(m.*list), ...); }, kEffectLists);
}

/// The effects and the filter of `from` in place of those of `to` (a diagnosed model's copy).
void assign_effects(NoiseModel& to, const NoiseModel& from);

/// Throws std::invalid_argument "<what>: <name>[i].<key>: <reason>" for the first effect in a
/// list (the filter aside: validate_lowpass) that breaks its traits' rules at m.rate_hz: every
/// key finite and by its KeyRule (a Presence::When key only when needed), then the effect's
/// check; or "<what>: at most N <name> effects, got M".
void validate_effects(const NoiseModel& m, const std::string& what);

/// Throws std::invalid_argument "lowpass.<key>: <reason>" (or "lowpass: <reason>") for a filter
/// that breaks its traits' rules at rate_hz: each key given (not 0) finite and by its KeyRule,
/// one of the two, then EffectTraits<Lowpass>::check. No filter (both 0) passes. simulate's
/// check of a model and analyze's --lowpass (where an infinite rate_hz checks the ranges alone,
/// the Nyquist frequency later per channel) share it with the model file's reader's rules.
void validate_lowpass(const Lowpass& lp, double rate_hz);

/// The model file's effect types, "sinusoid, markov, ... or lowpass", for a message.
std::string effect_type_list();

}  // namespace allanlot::kernels
