// The sinusoid effect: a line in the spectrum (a vibration, a thermal cycle). Everything about it
// that is not its synthesis (kernels/simulate/sinusoid.hpp): its name and model-file keys, its
// checks, its Allan variance.
#pragma once

#include "kernels/model/effects/effect.hpp"

#include <array>
#include <optional>

namespace allanlot::kernels {

/// A sinusoidal rate error A sin(2 pi f t + phase) (e.g. a vibration or a thermal cycle).
struct Sinusoid {
  double amplitude = 0;     // A [u], >= 0
  double frequency_hz = 0;  // f, 0 < f <= rate_hz / 2
  double phase_rad = 0;     // phase at t = 0
  friend bool operator==(const Sinusoid&, const Sinusoid&) = default;
};

template <>
struct EffectTraits<Sinusoid> {
  static constexpr std::string_view name = "sinusoid";
  static constexpr std::array<EffectKey<Sinusoid>, 3> keys = {{
      {"amplitude", &Sinusoid::amplitude, KeyRule::NonNegative, Presence::Required},
      {"frequency_hz", &Sinusoid::frequency_hz, KeyRule::Positive, Presence::Required},
      {"phase_rad", &Sinusoid::phase_rad, KeyRule::Finite, Presence::Optional},
  }};
  static constexpr std::size_t max_count = 0;
  // Its level (what the Allan variance scales with the square of) and its shape parameter.
  static constexpr double Sinusoid::*level = &Sinusoid::amplitude;
  static constexpr double Sinusoid::*shape = &Sinusoid::frequency_hz;
  // Frequency and amplitude come from the periodogram's line (diagnose's PSD witness).
  static constexpr int curve_parameters = 0;
  /// frequency_hz at most the Nyquist frequency rate_hz / 2 (the line is sampled).
  static std::optional<KeyProblem> check(const Sinusoid& s, double rate_hz, NumberText text);
};

/// The sinusoid's Allan variance at tau [s]: A^2 sin^4(pi f tau) / (pi f tau)^2, eq. (2) of the
/// paper applied to a line of power A^2 / 2; exact for the sampled record at tau = m / rate_hz
/// (each sample is the rate's mean over its interval, kernels/simulate/simulate.hpp).
double sinusoid_avar(const Sinusoid& s, double tau);

}  // namespace allanlot::kernels
