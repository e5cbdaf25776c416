// The sinusoid effect's process (kernels/simulate/effect_process.hpp): its samples, each the
// line's mean over its interval, and its shares of the Allan variance and the PSD.
#pragma once

#include "kernels/model/effects/sinusoid.hpp"
#include "kernels/simulate/effect_process.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace allanlot::kernels {

template <>
struct EffectProcess<Sinusoid> : DeterministicProcess {};

/// Adds the line to y (sample i is sample first + i of the record at rate_hz): the mean of
/// A sin(2 pi f t + p) over [t_k, t_k + h] is A sinc(pi f h) sin(2 pi f t_mid + p), exact in the
/// sampling model of kernels/simulate/simulate.hpp.
void add_effect_block(const Sinusoid& s, double rate_hz, std::size_t first, std::span<double> y);

/// sinusoid_avar (kernels/model/effects/sinusoid.hpp), exact at every m.
double effect_avar(const Sinusoid& s, double rate_hz, double tau);

/// The filter scales a line's power by |H(f)|^2 at its frequency (lowpass_gain2), and so its
/// Allan variance: exact.
double filter_change_avar(const Sinusoid& s, const FilterAt& at);

/// A line has no density: adds nothing (its power A^2 / 2 sits at its frequency alone).
void add_effect_psd(const Sinusoid& s, double rate_hz, std::span<const double> f_hz,
                    std::vector<double>& out);

}  // namespace allanlot::kernels
