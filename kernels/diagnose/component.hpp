// A diagnosis's model component: one part of the noise model (kernels/model/noise_model.hpp), an
// eq. (3) term at its level or one registered effect with its parameters in the model file's
// units, and what the search knows about it (free or fixed, given or added, searched or
// witnessed, the uncertainties that come from elsewhere). Code that needs one effect's fields
// reads them by name (as<E>); code that treats every part alike reads the effect's level and
// shape through EffectTraits (kernels/model/effects/effect.hpp).
#pragma once

#include "kernels/diagnose/diagnose.hpp"
#include "kernels/model/noise_model.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

namespace allanlot::kernels::diagnose_detail {

/// An eq. (3) term as a part of the model: its coefficient (R, K, B, N or Q).
struct TermLevel {
  Term term = Term::N;
  double coef = 0.0;
};

/// What a component is. The effects' alternatives follow Effect's order (diagnose.hpp): the
/// alternative of Effect e past the terms is index e - Effect::Sinusoid + 1 (checked below), so
/// the enum names the parts and a part its enum value.
using Part = std::variant<TermLevel, Sinusoid, GaussMarkov, Lowpass, Step, Resonance>;

template <Effect E>
using PartOf = std::variant_alternative_t<
    static_cast<std::size_t>(E) - static_cast<std::size_t>(Effect::Sinusoid) + 1, Part>;
static_assert(std::is_same_v<PartOf<Effect::Sinusoid>, Sinusoid> &&
              std::is_same_v<PartOf<Effect::Markov>, GaussMarkov> &&
              std::is_same_v<PartOf<Effect::Lowpass>, Lowpass> &&
              std::is_same_v<PartOf<Effect::Step>, Step> &&
              std::is_same_v<PartOf<Effect::Resonance>, Resonance> &&
              static_cast<int>(Effect::Resonance) + 1 == kNumEffects &&
              std::variant_size_v<Part> == kNumEffects - static_cast<int>(Effect::Sinusoid) + 1);

/// False for every type: the static_assert of a visit's branch that no part may reach.
template <class>
inline constexpr bool kUnhandled = false;

/// Whether effect E has a list in the noise model (kEffectLists), where spec_of puts it.
template <class E>
inline constexpr bool kListed = []<class... L>(std::tuple<L...>*) {
  return (std::is_same_v<L, std::vector<E> NoiseModel::*> || ...);
}(static_cast<std::remove_cvref_t<decltype(kEffectLists)>*>(nullptr));
// Every part but a term and the filter (which the model holds on its own) is a listed effect.
static_assert([]<std::size_t... I>(std::index_sequence<I...>) {
  return ((std::is_same_v<std::variant_alternative_t<I + 1, Part>, Lowpass> ||
           kListed<std::variant_alternative_t<I + 1, Part>>)&&...);
}(std::make_index_sequence<std::variant_size_v<Part> - 1>{}));

struct Component {
  Part part;
  bool free = false;     // its level re-estimated by the fit
  bool nl_free = false;  // its shape searched (for its uncertainty)
  bool given = false;    // part of the given model
  // The uncertainty of its shape parameter (EffectTraits<E>::shape: a line's or a resonance's
  // frequency, a jump's time) when that comes from elsewhere (the PSD, the record).
  double nl_sigma = std::numeric_limits<double>::quiet_NaN();
  // Its shape (a hump's tau_c, a resonance's frequency, the filter) at the lower (-1) or upper
  // (+1) end of its search range.
  int nl_bound = 0;
  int q_bound = 0;  // a resonance's q at an end of its search range
  // An added sinusoid's amplitude comes from the PSD line and is never refitted on the Allan
  // curve: there its bump overlaps any hump nearby (a Gauss-Markov effect at a similar tau),
  // which the amplitude would absorb, whereas the line's power above the local background is
  // the sinusoid's alone. A step's size comes from its jump in the record, for the same reason
  // (a random walk's or a ramp's rise would be absorbed).
  bool pinned = false;
  double coef_sigma = std::numeric_limits<double>::quiet_NaN();    // of its level when pinned
  double q_sigma = std::numeric_limits<double>::quiet_NaN();       // a resonance's q, its PSD fit
  double spread_sigma = std::numeric_limits<double>::quiet_NaN();  // a wandering resonance's
  bool psd_shape = false;  // a resonance's shape measured on the periodogram, sigma fitted
};

/// Whether c is an E (a term: TermLevel).
template <class E>
bool is(const Component& c) {
  return std::holds_alternative<E>(c.part);
}
template <class E>
E& as(Component& c) {
  return std::get<E>(c.part);
}
template <class E>
const E& as(const Component& c) {
  return std::get<E>(c.part);
}
/// Whether c is the eq. (3) term t.
inline bool is_term(const Component& c, Term t) {
  return is<TermLevel>(c) && as<TermLevel>(c).term == t;
}

/// The component of a part, its other facts at their defaults.
inline Component component(Part p) {
  Component c;
  c.part = p;
  return c;
}

/// The component's level as the model file has it: a term's coefficient, an effect's
/// EffectTraits level (a step's signed size); 1 for the filter, which has none and is present in
/// full.
inline double signed_level(const Component& c) {
  return std::visit(
      [](const auto& p) {
        using E = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<E, TermLevel>)
          return p.coef;
        else if constexpr (EffectTraits<E>::level == nullptr)
          return 1.0;
        else
          return p.*EffectTraits<E>::level;
      },
      c.part);
}

/// The level whose square scales the component's Allan variance (|size| for a step).
inline double coef(const Component& c) {
  return std::abs(signed_level(c));
}

/// Sets the level (v >= 0; a step keeps its direction); the filter has none to set.
inline void set_coef(Component& c, double v) {
  std::visit(
      [v](auto& p) {
        using E = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<E, TermLevel>)
          p.coef = v;
        else if constexpr (EffectTraits<E>::level != nullptr)
          p.*EffectTraits<E>::level = std::copysign(v, p.*EffectTraits<E>::level);
      },
      c.part);
}

/// The effect a component is (a term: the effect that adds it).
Effect effect_of(const Component& c);

}  // namespace allanlot::kernels::diagnose_detail
