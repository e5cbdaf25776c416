// The sensor's own anti-alias and decimation filter (docs/fit-and-psd.md): a linear time-invariant
// low-pass applied to the whole rate signal after synthesis, and what it does to the Allan
// variance. A real IMU's output is filtered and decimated inside the sensor, so its shortest-tau
// Allan deviation lies below the white-noise line the longer taus follow.
#pragma once

#include "kernels/model/effects/lowpass.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// The filter's impulse response on samples of rate_hz: a (1 - a)^j with
/// a = 1 - exp(-2 pi cutoff_hz / rate_hz) (the impulse-invariant one-pole filter, whose
/// continuous parent has its -3 dB point at cutoff_hz), truncated where the remaining tail is
/// below 1e-16 of the total; or floor(taps) values 1 / taps followed, for a non-integer taps,
/// by (taps - floor(taps)) / taps. {1} when inactive.
std::vector<double> lowpass_impulse(const Lowpass& lp, double rate_hz);

/// Filters `y` in place with the causal recursion of lowpass_impulse, started in the steady
/// state of the first sample (no start-up transient for a constant): sequential, so the same
/// bytes for any thread count.
void apply_lowpass(const Lowpass& lp, double rate_hz, std::span<double> y);

/// |H(f)|^2 of the filter at f_hz: a^2 / (1 - 2 (1 - a) cos w + (1 - a)^2) for the one-pole,
/// |sum_j h_j e^(-i w j)|^2 for the moving average, w = 2 pi f / rate_hz.
double lowpass_gain2(const Lowpass& lp, double rate_hz, double f_hz);

/// Ratio of the overlapping Allan variance at averaging factor m of a filtered to an unfiltered
/// noise, exact for the two white noises of eq. (3). White FM (N, white rate samples): the
/// Allan variance is (s^2 / 2) sum_k g_k^2 with g the filter convolved with the weights -1/m on
/// m samples then +1/m on the next m, 1 / m unfiltered. White PM (Q, white phase): the second
/// difference of the phase at lag m convolved with the filter, sum_k (h_k - 2 h_{k-m} +
/// h_{k-2m})^2 against 6 unfiltered. 1 when the filter is inactive.
double lowpass_white_fm_factor(const Lowpass& lp, double rate_hz, std::int64_t m);
double lowpass_white_pm_factor(const Lowpass& lp, double rate_hz, std::int64_t m);

/// The filter's autocorrelation rho_j = sum_i h_i h_{i+j}, j = 0 .. J-1 (h = lowpass_impulse,
/// J its length); {1} when inactive. What a filter does to any stationary noise's Allan variance
/// depends on h through rho alone.
std::vector<double> lowpass_autocorrelation(const Lowpass& lp, double rate_hz);

/// The overlapping Allan variance at averaging factor m (> 0) of a stationary noise whose sums
/// of k consecutive samples have variance d(k) (d(0) = 0), after the filter whose
/// autocorrelation is rho: with F(o) = sum_{|j| < J} rho_|j| d(|o - j|),
///
///   avar(m) = (8 F(m) - 2 F(2m) - 6 F(0)) / (4 m^2),
///
/// the variance of the filtered second difference of the phase at lag m written through the
/// phase's structure function d (for increments of a stationary process,
/// E[(x_a - x_b)(x_c - x_d)] = (d(a-d) + d(b-c) - d(a-c) - d(b-d)) / 2). Exact for integer m; a
/// non-integer m interpolates when d does.
double lowpass_structure_avar(const std::function<double(double)>& d, double m,
                              const std::vector<double>& rho);
/// F(o) of lowpass_structure_avar: the filtered structure function at lag o.
double lowpass_structure_sum(const std::function<double(double)>& d, double o,
                             const std::vector<double>& rho);

/// Overlapping Allan variance at averaging factor m (>= 1) of a Gauss-Markov effect of stationary
/// sd sigma and correlation time tau_c_s as simulate draws it (each sample the mean of the
/// Ornstein-Uhlenbeck process over its interval h = 1 / rate_hz), after the filter whose
/// autocorrelation is rho (lowpass_autocorrelation), exact: lowpass_structure_avar of the
/// variance of the sum of k consecutive samples, sigma^2 tau_c^2 v(k h / tau_c) / h^2 with
/// v(a) = 2 (a - 1 + e^-a). Unfiltered (rho = {1})
/// it is model_avar's sigma^2 tau_c^2 u(a) / tau^2. A tau_c near or below one sample makes the
/// effect white noise that the filter shapes like the white FM term: leaving the filter out of
/// its model would give it a shape of its own at the shortest taus that no simulation of it has.
double lowpass_markov_avar(double sigma, double tau_c_s, double rate_hz, std::int64_t m,
                           const std::vector<double>& rho);

/// The first averaging factor an eq. (3) fit of a filtered record may use: the smallest m from
/// which the filter changes white FM's overlapping Allan variance by less than half the
/// standard deviation of its estimate over n_samples (sqrt(2 / edf), Greenhall & Riley's white
/// FM edf), so that leaving the filter out of the fit biases no tau it uses by more than half a
/// sigma. (White PM keeps eq. (3)'s form under the filter: its Allan variance is scaled by the
/// filter's noise gain once m exceeds the filter's length, which a fitted Q absorbs.) 1 for an
/// inactive filter.
std::int64_t lowpass_first_m(const Lowpass& lp, double rate_hz, std::int64_t n_samples);

}  // namespace allanlot::kernels
