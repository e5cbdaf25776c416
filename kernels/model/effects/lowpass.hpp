// The lowpass effect: the sensor's own filter, applied to the sum of everything else
// (kernels/simulate/lowpass.hpp has its impulse response and what it does to each Allan
// variance). Here: its name and model-file keys, its checks (which validate_lowpass of
// kernels/model/noise_model.hpp applies with the keys' own rules). A channel has at most one; its
// JSON object has exactly one of the two keys.
#pragma once

#include "kernels/model/effects/effect.hpp"

#include <array>
#include <optional>

namespace allanlot::kernels {

/// At most one of the two forms; both zero means no filter.
struct Lowpass {
  double cutoff_hz = 0;  // first-order (one-pole) low-pass with this -3 dB frequency [Hz], > 0
  double taps = 0;       // moving average over this many samples, > 1 (non-integer: the last
                         // sample weighted by the fraction, a boxcar of taps tau0 seconds)
  bool active() const { return cutoff_hz > 0 || taps > 0; }
  friend bool operator==(const Lowpass&, const Lowpass&) = default;
};

/// The longest moving average a filter may have (taps): the model file's limit and simulate's.
inline constexpr int kLowpassMaxTaps = 100000;

template <>
struct EffectTraits<Lowpass> {
  static constexpr std::string_view name = "lowpass";
  // Exactly one of the two is given (and written).
  static constexpr std::array<EffectKey<Lowpass>, 2> keys = {{
      {"cutoff_hz", &Lowpass::cutoff_hz, KeyRule::Positive, Presence::OptionalNonzero},
      {"taps", &Lowpass::taps, KeyRule::Finite, Presence::OptionalNonzero},
  }};
  static constexpr std::size_t max_count = 1;
  // A filter has no level (it reshapes the others' variance) and two forms of its shape.
  static constexpr double Lowpass::*level = nullptr;
  static constexpr double Lowpass::*shape = nullptr;
  static constexpr int curve_parameters = 1;  // the cutoff or the taps, searched on the curve
  /// cutoff_hz below the Nyquist frequency; taps in (1, kLowpassMaxTaps].
  static std::optional<KeyProblem> check(const Lowpass& lp, double rate_hz, NumberText text);
};

}  // namespace allanlot::kernels
