// Diagnose's vocabulary of effects (docs/diagnose.md, the vocabulary): each effect's name as
// the JSON, the model file and the terminal spell it (an effect outside eq. (3): its own header's,
// kernels/model/effects/), and the eq. (3) term a term effect is.
#include "kernels/diagnose/diagnose.hpp"

#include "kernels/diagnose/internal.hpp"

#include <array>
#include <optional>
#include <string_view>
#include <utility>
#include <variant>

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

namespace allanlot::kernels::diagnose_detail {

Effect effect_of(const Component& c) {
  if (is<TermLevel>(c)) {
    for (const Effect e : kAllEffects)
      if (effect_term(e) == as<TermLevel>(c).term) return e;
  }
  // The effects' alternatives follow Effect's order (component.hpp).
  return static_cast<Effect>(static_cast<std::size_t>(Effect::Sinusoid) + c.part.index() - 1);
}

namespace {

template <std::size_t... I>
constexpr std::array<bool, kNumEffects> witnessed_table(std::index_sequence<I...>) {
  // The terms are fitted on the curve (a ramp's slope witness is asked only when the curve
  // names nothing: Search::witnessed_ramp); each effect past them by its traits.
  std::array<bool, kNumEffects> out{};
  ((out[static_cast<std::size_t>(Effect::Sinusoid) + I] =
        EffectTraits<std::variant_alternative_t<I + 1, Part>>::curve_parameters == 0),
   ...);
  return out;
}

constexpr std::array<bool, kNumEffects> kWitnessed =
    witnessed_table(std::make_index_sequence<std::variant_size_v<Part> - 1>{});

}  // namespace

bool witnessed_effect(Effect e) {
  return kWitnessed[static_cast<std::size_t>(e)];
}

}  // namespace allanlot::kernels::diagnose_detail
