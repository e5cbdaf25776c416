// Diagnose's vocabulary of effects (docs/diagnose.md, the vocabulary): each effect's name as
// the JSON, the model file and the terminal spell it (an effect outside eq. (3): its own header's,
// kernels/model/effects/), and the eq. (3) term a term effect is.
#include "kernels/diagnose/diagnose.hpp"

#include "kernels/diagnose/internal.hpp"

#include <optional>
#include <string_view>

namespace allanlot::kernels {

using diagnose_detail::kAllEffects;

std::string_view effect_name(Effect e) {
  switch (e) {
  case Effect::Quantization:
    return "quantization";
  case Effect::White:
    return "white";
  case Effect::Flicker:
    return "flicker";
  case Effect::RandomWalk:
    return "random_walk";
  case Effect::Ramp:
    return "ramp";
  case Effect::Sinusoid:
    return EffectTraits<Sinusoid>::name;
  case Effect::Markov:
    return EffectTraits<GaussMarkov>::name;
  case Effect::Lowpass:
    return EffectTraits<Lowpass>::name;
  case Effect::Step:
    return EffectTraits<Step>::name;
  case Effect::Resonance:
    return EffectTraits<Resonance>::name;
  }
  return "?";
}

std::optional<Effect> parse_effect(std::string_view name) {
  for (const Effect e : kAllEffects)
    if (effect_name(e) == name) return e;
  return std::nullopt;
}

std::optional<Term> effect_term(Effect e) {
  switch (e) {
  case Effect::Quantization:
    return Term::Q;
  case Effect::White:
    return Term::N;
  case Effect::Flicker:
    return Term::B;
  case Effect::RandomWalk:
    return Term::K;
  case Effect::Ramp:
    return Term::R;
  default:
    return std::nullopt;
  }
}

}  // namespace allanlot::kernels
