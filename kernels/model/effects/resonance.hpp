// The resonance effect: narrowband noise, the second-order Gauss-Markov process
// (kernels/simulate/resonance.hpp has its process, synthesis, Allan variance and PSD). Here: its
// name and model-file keys, its range of q and spread, its checks.
#pragma once

#include "kernels/model/effects/effect.hpp"

#include <array>
#include <optional>

namespace allanlot::kernels {

/// A resonance: narrowband noise of stationary standard deviation `sigma` [u] at `frequency_hz`
/// with quality factor `q` (about frequency_hz over its PSD's half-power width).
struct Resonance {
  double sigma = 0;         // stationary standard deviation [u], >= 0
  double frequency_hz = 0;  // f0, 0 < f0 < rate_hz / 2
  double q = 0;             // quality factor, kResonanceMinQ <= q <= kResonanceMaxQ
  double spread_hz = 0;     // sd of the frequency's slow wander; 0 (stationary) <= spread_hz
                            // <= resonance_max_spread(frequency_hz, rate_hz)
  double wander_s = 0;      // the wander's correlation time [s], > 0 when spread_hz > 0
  friend bool operator==(const Resonance&, const Resonance&) = default;
};

/// The range of q: at 0.5 the envelope decays within the oscillation's period (a hump, which
/// `markov` describes); above 1e5 the coherence time exceeds any record at any rate the
/// project meets, and the process is a line of random phase (`sinusoid`).
inline constexpr double kResonanceMinQ = 0.5;
inline constexpr double kResonanceMaxQ = 1e5;

/// The largest spread_hz at f0: a fifth of the distance to 0 or to the Nyquist frequency, so that
/// the mixture's nodes (4 standard deviations either side) and the wander stay inside.
double resonance_max_spread(double frequency_hz, double rate_hz);

template <>
struct EffectTraits<Resonance> {
  static constexpr std::string_view name = "resonance";
  static constexpr std::array<EffectKey<Resonance>, 5> keys = {{
      {"sigma", &Resonance::sigma, KeyRule::NonNegative, Presence::Required},
      {"frequency_hz", &Resonance::frequency_hz, KeyRule::Positive, Presence::Required},
      {"q", &Resonance::q, KeyRule::Finite, Presence::Required},
      {"spread_hz", &Resonance::spread_hz, KeyRule::NonNegative, Presence::OptionalNonzero},
      {"wander_s", &Resonance::wander_s, KeyRule::Positive, Presence::When,
       [](const Resonance& r) { return r.spread_hz > 0; }},
  }};
  // Each has its own random stream (kernels/simulate/resonance.hpp EffectProcess).
  static constexpr std::size_t max_count = 32;
  // Its shape is f0 and q; f0 is the one every resonance has a sigma for.
  static constexpr double Resonance::*level = &Resonance::sigma;
  static constexpr double Resonance::*shape = &Resonance::frequency_hz;
  // sigma, f0 and q searched on the curve (1, sigma alone, where the periodogram measured the
  // shape: diagnose's resonance_parameters).
  static constexpr int curve_parameters = 3;
  /// frequency_hz below the Nyquist frequency, q in [kResonanceMinQ, kResonanceMaxQ],
  /// spread_hz at most resonance_max_spread.
  static std::optional<KeyProblem> check(const Resonance& r, double rate_hz, NumberText text);
};

}  // namespace allanlot::kernels
