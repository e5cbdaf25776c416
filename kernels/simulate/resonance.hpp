// Narrowband noise: a resonance, the second-order Gauss-Markov process. Every ADIS16405 z
// gyroscope shows it (docs/diagnose.md "Real sensors: five ADIS16405 IMUs"): a PSD peak at 17-21
// Hz, about 0.2 Hz wide, holding about 0.06 (deg/s)^2, which no line (`sinusoid`: the periodogram
// resolves no single frequency) and no low-pass hump (`markov`) describes.
//
// The process is defined on the samples, as a sensor outputs it: the stationary AR(2)
//
//   x_k = a1 x_{k-1} + a2 x_{k-2} + e_k,   a1 = 2 r cos(theta),  a2 = -r^2,
//
// whose poles r e^(+-i theta) are the images at one sample interval h of a damped oscillator's,
// theta = 2 pi f0 h, r = exp(-pi f0 h / q): the PSD peaks near f0 and its half-power width is
// about f0 / q for q >> 1; the autocovariance's envelope decays with time constant q / (pi f0)
// (the coherence time). Its autocovariance (Yule-Walker: C(1) = a1 C(0) / (1 - a2), and C obeys
// the recursion for k >= 1) is, with z = r e^(i theta),
//
//   C(k) = Re[c z^k],  c = sigma^2 (1 - i b),  b = (rho1 / r - cos theta) / sin theta,
//   rho1 = a1 / (1 - a2),
//
// and the variance of a sum of k consecutive samples, from sum_{j<k} (k - j) z^j,
//
//   D(k) = Re[c (2 (z^(k+1) - (k+1) z + k) / (1 - z)^2 - k)],
//
// which the structure-function form of lowpass_structure_avar turns into the overlapping Allan
// variance under the sensor's filter. D is evaluated through g(x) = e^x - 1 - x of x = ln z, (k+1)
// ln z, so that a resonance far below the sample rate (z near 1) keeps its digits.
//
// A wandering resonance (spread_hz > 0): the frequency drifts slowly about f0, Gaussian with
// standard deviation spread_hz, as the ADIS16405 z gyroscopes' peak does with temperature (its
// frequency in 300 s pieces of a record moves over 18.4-20.8 Hz). Slow means against the
// coherence time, so the process is stationary resonances mixed over the frequency's law: its
// autocovariance, PSD and Allan variance are the mixture's, the Gaussian average of the
// stationary forms over f0 + spread_hz u, u standard normal (resonance_nodes: a trapezoidal rule).
// The simulation draws u as a Gauss-Markov process of correlation time wander_s, which sets how
// much a record's average over the wander varies from record to record (diagnose measures it
// on the frequency's track through the record).
#pragma once

#include "kernels/model/effects/resonance.hpp"
#include "kernels/simulate/effect_process.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::kernels {

/// Sequential over the record (the AR(2) recursion); effect i of a channel's list draws stream
/// 216 + i.
template <>
struct EffectProcess<Resonance> : RandomProcess<Resonance, Synthesis::Record, 216> {};

/// The mixture of a wandering resonance: stationary resonances (spread_hz 0, each of r's sigma)
/// and their weights (sum 1), by the trapezoidal rule over +-4 standard deviations of the
/// frequency with the normal density's weights; nodes at most half an sd and half the half-power
/// width f0 / (2 q) apart (at most 129). A stationary r is its own one node.
std::vector<std::pair<Resonance, double>> resonance_nodes(const Resonance& r);

/// The autocovariance C(k) of the samples at lags k = 0 .. n_lags - 1 (the closed form above).
std::vector<double> resonance_autocovariance(const Resonance& r, double rate_hz,
                                             std::size_t n_lags);

/// Overlapping Allan variance at averaging factor m (>= 1) after the filter of autocorrelation
/// rho (lowpass_autocorrelation; {1} unfiltered), exact for integer m. A non-integer m
/// interpolates smoothly (model_avar's tau between samples).
double resonance_avar(const Resonance& r, double rate_hz, double m,
                      const std::vector<double>& rho = {1.0});

/// resonance_avar at each averaging factor of m (each >= 1), the filter's constants computed
/// once: for m beyond the filter's length and the coherence's onset, a closed form of one
/// complex exponential (resonance.cpp).
std::vector<double> resonance_avar(const Resonance& r, double rate_hz,
                                   std::span<const std::int64_t> m, const std::vector<double>& rho);

/// One-sided PSD of the samples at f_hz, 2 h s_e^2 / |1 - a1 e^(-iw) - a2 e^(-2iw)|^2 with
/// w = 2 pi f h and s_e the innovation's sd: integrates to sigma^2 over (0, rate_hz / 2).
double resonance_psd_one_sided(const Resonance& r, double rate_hz, double f_hz);

/// The trigonometry of the resonances' one-sided PSD at a set of frequencies: cos w, sin w,
/// cos 2w, sin 2w with w = 2 pi f / rate_hz. It depends on the frequencies alone, so a fit that
/// evaluates the PSD over the same bins many times computes it once.
struct PsdTrig {
  std::vector<double> c1, s1, c2, s2;
  PsdTrig(std::span<const double> f_hz, double rate_hz);
  std::size_t size() const { return c1.size(); }
};

/// Adds scale times resonance_psd_one_sided at each frequency of `trig` to out (same size), the
/// mixture's nodes and their recursions' coefficients computed once: the form for fits over many
/// bins.
void add_resonance_psd(const Resonance& r, double rate_hz, double scale, const PsdTrig& trig,
                       std::span<double> out);
/// The same at the frequencies f_hz.
void add_resonance_psd(const Resonance& r, double rate_hz, double scale,
                       std::span<const double> f_hz, std::span<double> out);

/// Adds the process to y: x_0 and x_1 from the stationary joint law, then the recursion, its
/// innovations standard normals of `component`'s sequence of (seed, stream), index k for sample
/// k. Sequential, so the same bytes for any thread count; about 5 ns a sample. A wandering
/// resonance's frequency is f0 + spread_hz u_k, u the unit Gauss-Markov process of correlation
/// time wander_s whose innovations are the same sequence's from index 2^55 on, held within +-4;
/// its recursion's coefficients follow u every 8 samples.
void add_resonance(const Resonance& r, double rate_hz, std::uint64_t seed, std::uint64_t stream,
                   std::uint32_t component, std::span<double> y);

/// The effect's process hooks (kernels/simulate/effect_process.hpp): add_resonance; its Allan
/// variance resonance_avar at m = tau rate_hz (exact at whole samples, interpolated between
/// them), under the filter through the filter's autocorrelation (exact); its PSD
/// add_resonance_psd.
void add_effect_record(const Resonance& r, double rate_hz, std::uint64_t seed, std::uint64_t stream,
                       std::uint32_t component, std::span<double> y);
double effect_avar(const Resonance& r, double rate_hz, double tau);
double filter_change_avar(const Resonance& r, const FilterAt& at);
void add_effect_psd(const Resonance& r, double rate_hz, std::span<const double> f_hz,
                    std::vector<double>& out);

}  // namespace allanlot::kernels
