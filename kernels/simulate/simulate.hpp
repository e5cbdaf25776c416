// Time-domain synthesis of the noise terms of the paper's equation (3), and their theory.
//
// A simulated channel is the sum of independent components plus a constant offset:
//
//   y_k = offset + flicker(B) + white(N) + random_walk(K) + ramp(R) + quantization(Q)
//         + sum of sinusoids + sum of first-order Gauss-Markov processes + sum of resonances
//         + sum of steps,
//
// all of it then passed through the sensor's low-pass filter when the spec has one
// (kernels/simulate/lowpass.hpp). The effects outside eq. (3) are the registered ones
// (kernels/model/noise_model.hpp kEffectLists): simulate iterates them, each synthesized, and its
// share of the theory below given, by its process file (kernels/simulate/effect_process.hpp,
// e.g. kernels/simulate/markov.hpp),
//
// with every coefficient in the channel's own units u and seconds (docs/formats.md "Units
// and conventions"): R [u/s], K [u/s^0.5], B [u], N [u*s^0.5], Q [u*s], so that
//
//   avar(tau) = R^2 tau^2/2 + K^2 tau/3 + B^2 (2 ln 2/pi) + N^2/tau + 3 Q^2/tau^2   (eq. (3)).
//
// Sampling model. Sample k is the *mean* of the continuous-time rate over
// [k tau0, (k+1) tau0], as an integrating sensor delivers it; the phase x_k = tau0 sum_{j<k} y_j
// is then exactly the continuous angle (velocity, time error) at t_k, and the Allan variance of
// the samples at tau = m tau0 equals the continuous-time value at every m. White noise, random
// walk, ramp, quantization, sinusoids and Gauss-Markov are synthesized exactly in this sense. A
// resonance (kernels/simulate/resonance.hpp) is a process on the samples themselves, as the
// sensor's output shows it; its Allan variance is exact at every m too.
// Flicker is the exception: Kasdin's discrete 1/f sequence (Kasdin 1995) has no continuous
// parent, and its Allan variance exceeds the eq. (3) floor at small m by flicker_avar_factor(m)
// (1.44 at m = 1, 1.15 at m = 2, 1.0013 at m = 32); model_avar_sampled() includes that factor.
//
// Reproducibility. Every random number is a pure function of (seed, stream, component, index)
// (kernels/simulate/rng.hpp, Philox4x32-10); samples are produced in fixed-size blocks, each by one
// thread, and sequential carries (random walk, Gauss-Markov state) are combined in block
// order; FFTW plans are made with FFTW_ESTIMATE on fftw_malloc'ed buffers, so the plan (and
// its rounding) does not depend on timing. Same spec, seed and stream: the same bytes for any
// thread count, with or without OpenMP. Each sample's sum is added in one fixed order: flicker,
// offset, white, random walk, ramp, quantization, the Block effects, the Carried effects (each
// stage's effects in kEffectLists order), the block start states, flicker PM, the Record
// effects; then the filter and the output's rounding.
#pragma once

#include "kernels/model/noise_model.hpp"
#include "kernels/simulate/effects.hpp"
#include "kernels/simulate/lowpass.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// Everything that defines one simulated channel: the noise model (kernels/model/noise_model.hpp).
using ChannelSpec = NoiseModel;

/// Checks a spec; throws std::invalid_argument naming the field and its value: rate_hz finite
/// and > 0; every coefficient finite and >= 0; offset finite; the lowpass as validate_lowpass;
/// each effect by its traits' rules (validate_effects, kernels/model/noise_model.hpp: e.g. a
/// sinusoid's frequency_hz in (0, rate_hz / 2], at most 200 markov and 32 resonance effects).
void validate(const ChannelSpec& spec);

/// Owns the workspaces and FFTW plans for simulating channels of one length, so that a unit's
/// channels (and a lot's units) share the flicker filter's spectrum, which is computed once,
/// on the first channel that has B > 0. Non-copyable; not safe to run() from two threads at
/// once (use one plan per thread). Memory: about 4 n doubles once flicker is used (filter
/// spectrum plus one FFT block), none before.
///
/// Flicker (Kasdin 1995, "Discrete simulation of colored noise and stochastic processes and
/// 1/f^alpha power law noise generation", Proc. IEEE 83(5)): white Gaussian w_j of variance
/// Q_d filtered by h_0 = 1, h_k = h_{k-1} (alpha/2 + k - 1) / k with alpha = 1, i.e.
/// (1 - z^-1)^(-1/2). Its two-sided PSD is Q_d tau0 / (2 sin(pi f tau0)) -> Q_d / (2 pi f) for
/// f << rate_hz, the paper's B^2 / (2 pi f) when Q_d = B^2: so w_j = B g_j with g_j standard
/// normal. The filter has n taps (the whole record), applied by overlap-save FFT convolution.
class SimulationPlan {
public:
  /// Plan for channels of `n_samples` samples (>= 1). `flicker_block` is the minimum number of
  /// output samples per overlap-save block; 0 chooses n_samples, i.e. one FFT of size
  /// >= 2 n - 1. Smaller blocks mean smaller FFTs but more of them and the same filter
  /// spectrum size; the results agree to FFT rounding (~1e-15 relative), not bitwise, so a
  /// reproducible workflow must keep the default.
  explicit SimulationPlan(std::size_t n_samples, std::size_t flicker_block = 0);
  ~SimulationPlan();
  SimulationPlan(const SimulationPlan&) = delete;
  SimulationPlan& operator=(const SimulationPlan&) = delete;

  std::size_t size() const;
  /// Fills `out` (exactly size() samples) with the channel described by `spec`, drawn from the
  /// random streams keyed by (seed, stream). `nthreads` as kernels::resolve_threads (0 = the
  /// OpenMP default). Throws std::invalid_argument for a bad spec or a wrong out.size().
  void run(const ChannelSpec& spec, std::uint64_t seed, std::uint64_t stream, std::span<double> out,
           int nthreads = 0);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot form of SimulationPlan(out.size()).run(...): fills `out` (rate data, n samples)
/// deterministically from (seed, stream). Use a distinct stream per channel (and per unit).
void simulate_channel(const ChannelSpec& spec, std::uint64_t seed, std::uint64_t stream,
                      std::span<double> out, int nthreads = 0);

/// Kasdin's flicker (alpha = 1) filter h_0 .. h_{n-1}: h_0 = 1, h_k = h_{k-1} (k - 1/2) / k,
/// i.e. h_k = Gamma(k + 1/2) / (Gamma(1/2) k!) ~ 1 / sqrt(pi k).
std::vector<double> kasdin_flicker_filter(std::size_t n);

/// Continuous-time Allan variance of the spec at tau_s (> 0), in u^2: the five eq. (3) terms,
/// plus A^2 sin^4(pi f tau) / (pi f tau)^2 for each sinusoid (eq. (2) applied to a line of
/// power A^2/2) and, for each Gauss-Markov effect with a = tau / tau_c,
/// sigma^2 tau_c^2 (2a - 3 + 4 e^-a - e^-2a) / tau^2, which is K^2 tau/3 with
/// K^2 = 2 sigma^2 / tau_c for tau << tau_c and N^2 / tau with N^2 = 2 sigma^2 tau_c for
/// tau >> tau_c (IEEE Std 952-1997, annex C). The offset does not contribute, and neither do
/// the steps: a single jump's share of an Allan variance falls as 1 / (record length) (see
/// step_avar_sampled), so over the unbounded record this continuous form describes it is zero.
/// A resonance adds resonance_avar at m = tau_s rate_hz (exact at whole samples, interpolated
/// between them). Each effect's share is its process's effect_avar.
double model_avar(const ChannelSpec& spec, double tau_s);

/// Expected overlapping Allan variance of simulate_channel's output at tau = m / rate_hz
/// (m >= 1): model_avar with the flicker term multiplied by flicker_avar_factor(m) and, under a
/// low-pass filter, the white FM and white PM terms by lowpass_white_fm_factor and
/// lowpass_white_pm_factor (exact), each sinusoid's by lowpass_gain2 at its frequency (exact)
/// and each Gauss-Markov effect's as lowpass_markov_avar (exact: a tau_c near one sample makes it
/// white noise, which the filter shapes), each resonance's as resonance_avar under the filter's
/// autocorrelation (exact); the filter's effect on flicker, random walk and ramp
/// is left out: their power lies far below any cutoff at the taus where they matter (at tau0 a
/// flicker floor loses a fraction of itself to a cutoff near Nyquist, which the model leaves
/// out). Exact for all components at every m, apart from the finite record's effect on flicker (the
/// filter starts at the first sample, so the earliest terms miss the pre-record past: a deficit of
/// relative order m / n, negligible for m << n). With n_samples > 0 (the record's length, at
/// least 2 m) each step adds step_avar_sampled, exactly (the filter's smoothing of the jump is
/// left out, as the ramp's); with n_samples = 0 (an unbounded record) the steps add nothing.
/// Each effect's share over the record is its process's plus_record_avar, under the filter its
/// filter_change_avar.
double model_avar_sampled(const ChannelSpec& spec, std::int64_t m, std::int64_t n_samples = 0);

/// Ratio of the Allan variance of Kasdin's discrete flicker sequence at averaging factor m to
/// the continuous floor B^2 2 ln2 / pi. From the PSD above and the discrete averaging
/// transfer function, avar(m) = (2 B^2 / pi) I(m) with
///   I(m) = integral_0^{pi/2} sin^4(m x) / (m^2 sin^3 x) dx,
/// and I(m) -> integral_0^inf sin^4(u)/u^3 du = ln 2 as m -> inf (I(1) = 1, I(2) = 4/5).
/// Evaluated by composite Gauss-Legendre quadrature for m <= 4096; beyond, the correction
/// (about (3/16) ln(m) / (m^2 ln 2)) is below 2e-7 and 1 is returned.
double flicker_avar_factor(std::int64_t m);

/// One-sided PSD of the spec's stochastic components at f_hz (> 0), in u^2/Hz: the paper's
/// forms under eq. (3), which are two-sided S(f) in the convention of its eq. (2), doubled
/// (docs/formats.md): K^2 / (2 pi^2 f^2) + B^2 / (pi f) + 2 N^2 + 2 (2 pi f)^2 Q^2 tau0, plus
/// 4 sigma^2 tau_c / (1 + (2 pi f tau_c)^2) per Gauss-Markov effect, and each resonance's
/// resonance_psd_one_sided (the samples' own spectrum, exact up to Nyquist). These are the
/// continuous-time forms, valid for f << rate_hz / 2 (the sampled flicker and quantization
/// spectra are 1/(2 sin(pi f tau0)) and sin^2(pi f tau0) shaped near Nyquist). The ramp and the
/// sinusoids are deterministic (no density; a sinusoid is a line of power A^2/2 at its
/// frequency) and contribute nothing here; the offset neither.
double model_psd_one_sided(const ChannelSpec& spec, double f_hz);
/// The same at each frequency of f_hz (each > 0 and finite), each resonance's nodes computed
/// once: the form for integrals over many frequencies.
std::vector<double> model_psd_one_sided(const ChannelSpec& spec, std::span<const double> f_hz);

}  // namespace allanlot::kernels
