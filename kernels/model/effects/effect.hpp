// What every effect of the noise model declares about itself (kernels/model/noise_model.hpp):
// the traits each effect's own header specialises, so that the model file, simulate's checks
// and diagnose read one owner per fact. An effect is a value type (one struct of doubles); its
// traits give
//
//   name              the effect's name in the model file ("type"), diagnose's vocabulary, the
//                     JSON and the terminal
//   keys              its model-file keys in the order they are read and written, each a field
//                     of the struct with its rule and whether it may be left out
//   max_count         the most a channel may hold (0: no limit)
//   curve_parameters  the parameters diagnose fits on the Allan curve when it adds one (0: a
//                     witnessed effect, whose parameters come from the record itself)
//   level             the field its Allan variance scales with the square of (null for the
//                     filter, which reshapes the others' variance instead)
//   shape             the field that sets where on the tau axis it acts (a frequency, a
//                     correlation time, a time; null for the filter, whose two forms differ)
//   check             the rules that tie a value to others or to the sample rate, beyond each
//                     key's own rule (the reason worded as the model file reports it)
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace allanlot::kernels {

/// The rule a key's number obeys on its own (always finite).
enum class KeyRule { Finite, NonNegative, Positive };

/// Whether a key must be given, and when it is written.
enum class Presence {
  Required,         // must be given; always written
  Optional,         // may be left out (0); always written
  OptionalNonzero,  // may be left out (0); written when not 0
  When,             // read (and then required) and written only when EffectKey::needed holds
};

/// One model-file key of effect E: the field it sets.
template <class E>
struct EffectKey {
  std::string_view name;
  double E::*field = nullptr;
  KeyRule rule = KeyRule::Finite;
  Presence presence = Presence::Required;
  bool (*needed)(const E&) = nullptr;  // Presence::When: the keys before it decide
};

/// Whether key k of effect x is written (the model file, a results file's effect rows): as its
/// Presence says.
template <class E>
bool written(const EffectKey<E>& k, const E& x) {
  switch (k.presence) {
  case Presence::Required:
  case Presence::Optional:
    return true;
  case Presence::OptionalNonzero:
    return x.*k.field != 0;
  case Presence::When:
    return k.needed(x);
  }
  return false;
}

/// A value that breaks an effect's rule: the key (empty: the effect as a whole) and the reason.
struct KeyProblem {
  std::string key;
  std::string reason;
};

/// How a reason spells a number (the model file: its JSON form).
using NumberText = std::string (*)(double);

/// Specialised by each effect's header (kernels/model/effects/<name>.hpp).
template <class E>
struct EffectTraits;

}  // namespace allanlot::kernels
