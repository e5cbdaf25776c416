// The markov effect: a first-order Gauss-Markov process, a hump in the Allan deviation. Everything
// about it that is not its synthesis (kernels/simulate/markov.hpp): its name and model-file keys,
// its Allan variance and PSD.
#pragma once

#include "kernels/model/effects/effect.hpp"

#include <array>
#include <optional>

namespace allanlot::kernels {

/// First-order Gauss-Markov (Ornstein-Uhlenbeck) rate error: stationary, autocovariance
/// sigma^2 exp(-|t| / tau_c).
struct GaussMarkov {
  double sigma = 0;    // stationary standard deviation [u], >= 0
  double tau_c_s = 0;  // correlation time [s], > 0
  friend bool operator==(const GaussMarkov&, const GaussMarkov&) = default;
};

template <>
struct EffectTraits<GaussMarkov> {
  static constexpr std::string_view name = "markov";
  static constexpr std::array<EffectKey<GaussMarkov>, 2> keys = {{
      {"sigma", &GaussMarkov::sigma, KeyRule::NonNegative, Presence::Required},
      {"tau_c_s", &GaussMarkov::tau_c_s, KeyRule::Positive, Presence::Required},
  }};
  // Each has its own random stream (kernels/simulate/markov.hpp EffectProcess).
  static constexpr std::size_t max_count = 200;
  static constexpr double GaussMarkov::*level = &GaussMarkov::sigma;
  static constexpr double GaussMarkov::*shape = &GaussMarkov::tau_c_s;
  static constexpr int curve_parameters = 2;  // sigma and tau_c, both fitted on the curve
  static std::optional<KeyProblem> check(const GaussMarkov&, double, NumberText) {
    return std::nullopt;
  }
};

/// u(a) = 2a - 3 + 4 e^-a - e^-2a = sum_{k>=3} (-1)^k (4 - 2^k) a^k / k!. It is the
/// Gauss-Markov Allan variance (times tau^2 / (sigma tau_c)^2) and the variance of the
/// integral of an OU process over a step given its start; it behaves as (2/3) a^3 for small a,
/// where the closed form cancels catastrophically, so the series is used below a = 0.5 (where
/// its terms fall below 1e-17 relative by k = 25).
double markov_u(double a);

/// The Allan variance at tau [s], sigma^2 tau_c^2 u(tau / tau_c) / tau^2 with a = tau / tau_c
/// (IEEE Std 952-1997, annex C): K^2 tau / 3 with K^2 = 2 sigma^2 / tau_c for tau << tau_c and
/// N^2 / tau with N^2 = 2 sigma^2 tau_c for tau >> tau_c; unfiltered, exact at every m.
double markov_avar(const GaussMarkov& g, double tau);

/// The one-sided PSD at angular frequency w = 2 pi f: 4 sigma^2 tau_c / (1 + (w tau_c)^2).
double markov_psd_one_sided(const GaussMarkov& g, double w);

}  // namespace allanlot::kernels
