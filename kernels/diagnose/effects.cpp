// Diagnose's vocabulary of effects (docs/diagnose.md, the vocabulary): each effect's name as
// the JSON, the model file and the terminal spell it, and the eq. (3) term a term effect is. The
// effects outside eq. (3) are the model's parts (component.hpp): their names and whether a
// witness names them come from their own headers' EffectTraits (kernels/model/effects/).
#include "kernels/diagnose/diagnose.hpp"

#include "kernels/diagnose/internal.hpp"

#include <array>
#include <optional>
#include <string_view>
#include <utility>
#include <variant>

namespace allanlot::kernels::diagnose_detail {
namespace {

// The term effects, in Effect's order, with the eq. (3) term each adds.
constexpr std::array<std::pair<std::string_view, Term>, 5> kTermEffects = {{
    {"quantization", Term::Q},
    {"white", Term::N},
    {"flicker", Term::B},
    {"random_walk", Term::K},
    {"ramp", Term::R},
}};
static_assert(kTermEffects.size() == static_cast<std::size_t>(Effect::Sinusoid));

// One fact of every effect, indexed by Effect: `term_fact` for the term effects, `fact` of
// each part's traits for the effects past them.
template <class T, class TermFact, class Fact, std::size_t... I>
constexpr std::array<T, kNumEffects> effect_table(TermFact term_fact, Fact fact,
                                                  std::index_sequence<I...>) {
  std::array<T, kNumEffects> out{};
  for (std::size_t e = 0; e < kTermEffects.size(); ++e)
    out[e] = term_fact(kTermEffects[e]);
  ((out[kTermEffects.size() + I] = fact(EffectTraits<std::variant_alternative_t<I + 1, Part>>{})),
   ...);
  return out;
}
constexpr auto kParts = std::make_index_sequence<std::variant_size_v<Part> - 1>{};

constexpr std::array<std::string_view, kNumEffects> kNames =
    effect_table<std::string_view>([](const auto& t) { return t.first; },
                                   [](auto traits) { return decltype(traits)::name; }, kParts);

// The terms are fitted on the curve (a ramp's slope witness is asked only when the curve names
// nothing: Search::witnessed_ramp); an effect whose curve_parameters are 0 is not.
constexpr std::array<bool, kNumEffects> kWitnessed =
    effect_table<bool>([](const auto&) { return false; },
                       [](auto traits) { return decltype(traits)::curve_parameters == 0; }, kParts);

}  // namespace

Effect effect_of(const Component& c) {
  if (is<TermLevel>(c)) {
    for (std::size_t e = 0; e < kTermEffects.size(); ++e)
      if (kTermEffects[e].second == as<TermLevel>(c).term) return static_cast<Effect>(e);
  }
  // The effects' alternatives follow Effect's order (component.hpp).
  return static_cast<Effect>(kTermEffects.size() + c.part.index() - 1);
}

bool witnessed_effect(Effect e) {
  return kWitnessed[static_cast<std::size_t>(e)];
}

}  // namespace allanlot::kernels::diagnose_detail

namespace allanlot::kernels {

using diagnose_detail::kAllEffects;
using diagnose_detail::kNames;
using diagnose_detail::kTermEffects;

std::string_view effect_name(Effect e) {
  return kNames[static_cast<std::size_t>(e)];
}

std::optional<Effect> parse_effect(std::string_view name) {
  for (const Effect e : kAllEffects)
    if (effect_name(e) == name) return e;
  return std::nullopt;
}

std::optional<Term> effect_term(Effect e) {
  const auto i = static_cast<std::size_t>(e);
  if (i < kTermEffects.size()) return kTermEffects[i].second;
  return std::nullopt;
}

}  // namespace allanlot::kernels
