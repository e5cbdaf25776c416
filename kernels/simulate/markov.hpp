// The markov effect's process (kernels/simulate/effect_process.hpp): a first-order Gauss-Markov
// state carried across blocks by the random walk's engine, each sample the state's mean over its
// interval, and its shares of the Allan variance (plain and under the filter) and the PSD.
#pragma once

#include "kernels/model/effects/markov.hpp"
#include "kernels/simulate/effect_process.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// Effect i of a channel's list draws stream 16 + i.
template <>
struct EffectProcess<GaussMarkov> : RandomProcess<GaussMarkov, Synthesis::Carried, 16> {};

/// The exact discretization of the Ornstein-Uhlenbeck process over one sample interval h (the
/// Cholesky factor of the state's and the interval integral's joint law); none for sigma = 0,
/// which draws nothing. Its pair 0 draws the stationary start, pair k + 1 sample k.
std::optional<CarriedStep> carried_step(const GaussMarkov& g, double h);

/// markov_avar (kernels/model/effects/markov.hpp), exact at every m.
double effect_avar(const GaussMarkov& g, double rate_hz, double tau);

/// lowpass_markov_avar less markov_avar: exact (a tau_c near one sample makes the effect white
/// noise, which the filter shapes).
double filter_change_avar(const GaussMarkov& g, const FilterAt& at);

/// Adds markov_psd_one_sided at each frequency of f_hz to out.
void add_effect_psd(const GaussMarkov& g, double rate_hz, std::span<const double> f_hz,
                    std::vector<double>& out);

}  // namespace allanlot::kernels
