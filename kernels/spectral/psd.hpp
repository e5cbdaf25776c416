// Power spectral density of a rate channel (Welch), its log-frequency binning, and the
// paper's equation (2) evaluated on the measured PSD (the `psd/` and `crosscheck/` groups of
// the results layout, docs/formats.md).
//
// Conventions (docs/formats.md "Units and conventions"): every PSD here is one-sided, in
// u^2/Hz, on 0 <= f <= rate_hz / 2; eq. (2) of the paper uses the two-sided
// S(f) = one-sided / 2, so white noise of coefficient N has one-sided PSD 2 N^2.
//
// Reproducibility. Each segment's periodogram is computed by one thread into its own row, with
// a plan from the stored FFTW wisdom (or FFTW_ESTIMATE's; never one timed in the run) on
// 64-byte aligned buffers, and the rows are added in segment order afterwards; eq. (2) is one
// fixed-order sum per tau. Results are therefore bit-identical for any thread count, with or
// without OpenMP.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// Welch estimate of the one-sided PSD of one channel.
struct PsdResult {
  std::vector<double> f_hz;  // bin frequencies k * df_hz, k = 0 .. L/2 (DC and Nyquist included)
  std::vector<double> psd;   // one-sided PSD [u^2/Hz]; bin 0 holds only leakage (see welch)
  std::vector<double> edf;   // equivalent chi-square degrees of freedom of each bin
  double rate_hz = 0;        // sample rate of the input
  double df_hz = 0;          // bin spacing rate_hz / L
  std::int64_t segment_length = 0;  // L, samples per segment (even)
  std::int64_t n_segments = 0;      // segments averaged (gap-free)
  std::int64_t n_skipped = 0;       // segments left out because they touch a NaN sample
  std::size_t size() const { return f_hz.size(); }
};

/// Number of 50 %-overlapping segments of length L (hop L/2) that fit in n samples:
/// floor((n - L) / (L/2)) + 1, or 0 when n < L.
std::int64_t welch_segment_count(std::int64_t n_samples, std::int64_t segment_length);

/// The segment-length rule: the largest power of two L >= 16 whose 50 %-overlapping segments
/// number at least `min_segments` (>= 1) in n_samples, i.e. roughly n / (min_segments / 2 + 0.5).
///
/// Why: the variance of a Welch bin is ~ S^2 / (0.95 n_seg) (edf ~ 1.9 n_seg for Hann at 50 %
/// overlap), so 16 segments give edf ~ 30, a 1-sigma scatter of ~ 26 % per bin before any
/// log binning; halving L doubles the edf but doubles the lowest usable frequency (2 df =
/// 2 rate_hz / L, bin 1 is biased by the per-segment mean removal), and the low end is where
/// flicker and random walk show. For the paper's gyros (flicker/white corner
/// B^2 / (2 pi N^2) ~ 0.01 Hz at 1 kHz) 16 segments put 2 df below the corner only for
/// records of >= 2.23e6 samples (37 min; the paper's 90 min give 2 df = 0.004 Hz); with shorter
/// records pass a smaller `min_segments` (e.g. 8) to trade scatter for resolution. A power of two
/// keeps the FFT fast. Throws std::invalid_argument (naming n_samples) when even L = 16 gives fewer
/// segments.
std::int64_t welch_segment_length(std::int64_t n_samples, std::int64_t min_segments = 16);

/// Owns the FFTW plan and the window for Welch PSDs with one segment length, so that every
/// channel of a unit (and every unit of a lot) with that length reuses them. Non-copyable; the
/// plan is made and destroyed under detail::fftw_planner_mutex() (kernels/spectral/fft.hpp).
/// welch() is const and may be called from several threads at once (it executes the plan on its own
/// buffers with FFTW's new-array interface, which is thread-safe).
class PsdPlan {
public:
  /// Plan for segments of `segment_length` samples: even, >= 16 and < 2^30 (std::invalid_argument
  /// naming segment_length otherwise).
  explicit PsdPlan(std::int64_t segment_length);
  ~PsdPlan();
  PsdPlan(const PsdPlan&) = delete;
  PsdPlan& operator=(const PsdPlan&) = delete;

  std::int64_t segment_length() const;

  /// The process's one plan of `segment_length` (made on first use, kept until exit), shared by
  /// every channel and thread: welch_psd uses it, so a lot plans each segment length once.
  static const PsdPlan& shared(std::int64_t segment_length);

  /// True when the transform was planned from the stored FFTW wisdom (fft::Plan::r2c_stored),
  /// false when FFTW_ESTIMATE planned it (a length the wisdom lacks, or a CPU without its SIMD).
  bool from_wisdom() const;

  /// Welch's method (P. D. Welch, IEEE Trans. Audio Electroacoust. 15(2), 1967) on rate samples
  /// y_0 .. y_{n-1} taken at rate_hz:
  ///  - segments j = 0, 1, ... start at j L/2 (50 % overlap); a segment containing a NaN
  ///    sample (a gap) is skipped and counted in n_skipped;
  ///  - each segment has its own mean removed (so that the random walk's wandering level does
  ///    not leak into the low bins), is multiplied by the periodic Hann window
  ///    w_t = 0.5 - 0.5 cos(2 pi t / L), and transformed: X_k = sum_t w_t y_t e^{-2 pi i k t / L};
  ///  - normalization, explicit: P_k = c_k |X_k|^2 / (rate_hz * sum_t w_t^2), with c_k = 2 for
  ///    0 < k < L/2 (one-sided: the negative frequencies folded in) and c_k = 1 at k = 0 and
  ///    k = L/2. Then sum_k P_k df = sum_t (w_t y_t)^2 / sum_t w_t^2 (discrete Parseval): the
  ///    window-weighted mean square of the segment, which equals its variance on average;
  ///  - psd = the mean of P_k over the used segments, added in segment order.
  /// Bin 0 holds only the Hann leakage from bin 1 (the segment mean is removed) and bin 1 is
  /// biased low by 1/6 for a locally flat spectrum (its Hann neighbour bin 0 is emptied);
  /// bins k >= 2 are unbiased for a spectrum smooth over a few bins. edf per bin (Percival &
  /// Walden, "Spectral Analysis for Physical Applications", 1993, eq. (292b)):
  /// nu = 2 n^2 / (n + 2 rho^2 n_adj), n segments, n_adj of them adjacent (overlapping) pairs,
  /// rho = sum_t w_t w_{t+L/2} / sum_t w_t^2 = 1/6 for Hann; halved at k = 0 and L/2
  /// (real-valued bins).
  /// Preconditions (std::invalid_argument naming the parameter): rate_hz finite and > 0;
  /// rate.size() >= L; no infinite sample in rate; at least one gap-free segment in rate.
  PsdResult welch(std::span<const double> rate, double rate_hz, int nthreads = 0) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot Welch PSD with the segment length welch_segment_length(rate.size(), min_segments).
PsdResult welch_psd(std::span<const double> rate, double rate_hz, int nthreads = 0,
                    std::int64_t min_segments = 16);

/// A PSD averaged over log-spaced frequency bins.
struct BinnedPsd {
  std::vector<double> f_hz;         // mean frequency of the Welch bins averaged
  std::vector<double> psd;          // their mean PSD [u^2/Hz], one-sided
  std::vector<std::int64_t> n_avg;  // number of Welch bins averaged
  std::vector<double> edf;          // chi-square degrees of freedom of the mean (see log_bin)
  std::size_t size() const { return f_hz.size(); }
};

/// Averages the Welch bins k >= 1 into `bins_per_decade` (>= 1) bins per decade, with edges
/// at f = 10^(i / bins_per_decade) Hz (so bins line up across channels and rates); the
/// first `n_linear` (>= 0) bins k = 1 .. n_linear are kept as they are, since a log bin there
/// would hold at most one Welch bin anyway. Empty log bins give no row. Bin 0 (DC, leakage
/// only) is dropped. The edf of a mean of n adjacent Welch bins of edf nu each is
/// nu n^2 / (n + 2 sum_{d>=1} (n - d) r_d), r_d the correlation of two periodogram bins d
/// apart for a locally white spectrum: r_d = |sum_t w_t^2 e^{-2 pi i d t/L}|^2 / (sum_t w_t^2)^2,
/// i.e. r_1 = 4/9, r_2 = 1/36, r_d = 0 beyond for Hann (Percival & Walden sec. 6.6).
/// Throws std::invalid_argument naming bins_per_decade or n_linear when out of range.
BinnedPsd log_bin(const PsdResult& psd, int bins_per_decade = 10, int n_linear = 4);

/// Options of avar_from_psd.
struct AvarPsdOptions {
  double max_low_fraction = 0.10;  // valid tau: extrapolated share of avar <= this (0 .. 1)
  double max_m_fraction = 0.125;   // valid tau: tau * rate_hz <= this * L (resolution)
  std::int64_t first_bin = 2;      // lowest Welch bin summed (>= 1); below: power law
  double fit_decades = 1.0;        // power law fitted on bins first_bin .. first_bin*10^this
};

/// Equation (2) on a measured PSD, for each tau.
struct AvarPsdResult {
  std::vector<double> tau_s;        // as given
  std::vector<double> avar;         // avar_band + avar_low [u^2] (avar_band without fit)
  std::vector<double> avar_band;    // the Welch bins' part
  std::vector<double> avar_low;     // the power-law part below f_low_hz (NaN: no fit)
  std::vector<std::uint8_t> valid;  // 1 where the options' two criteria hold
  double tau_valid_min = 0;         // smallest and largest valid tau (NaN when none is)
  double tau_valid_max = 0;
  double f_low_hz = 0;         // (first_bin - 1/2) df: the band summed is [f_low_hz, rate_hz/2]
  double low_exponent = 0;     // a of the fitted one-sided PSD A f^a below f_low_hz
  double low_coefficient = 0;  // A [u^2/Hz^(1+a)]
  bool low_fit_ok = false;     // false when a <= -3 (eq. (2) diverges at f -> 0) or the fit failed
  std::size_t size() const { return tau_s.size(); }
};

/// Allan variance of the sampled sequence from its one-sided PSD S1 (u^2/Hz):
///
///   avar(tau) = integral_0^{rate_hz/2} S1(f) |H_m(f)|^2 df,
///   |H_m(f)|^2 = 2 sin^4(pi f m tau0) / (m sin(pi f tau0))^2,   m = tau / tau0,
///
/// the discrete-time form of the paper's eq. (2) (4 S2 sin^4(pi f tau)/(pi f tau)^2 with
/// S2 = S1/2). Derivation: the Allan variance is (1/2) E (ybar_{j+m} - ybar_j)^2 with ybar_j
/// the mean of m samples; that difference is y filtered by a length-m moving average,
/// |A(f)| = |sin(pi f m tau0) / (m sin(pi f tau0))|, followed by (1 - z^-m),
/// |1 - e^{-2 pi i f m tau0}| = 2 |sin(pi f m tau0)|; the variance of the output is
/// integral_{-fs/2}^{fs/2} S2 |.|^2 df = integral_0^{fs/2} S1 (...) df, and the factor 1/2 gives
/// |H_m|^2 above. As f tau0 -> 0, m sin(pi f tau0) -> pi f tau and the continuous kernel is
/// recovered; near Nyquist they differ: at m = 1, f = fs/2 the discrete weight is 2, the
/// continuous one 2 (2/pi)^2 = 0.81, and white noise (S1 = 2 N^2) gives exactly N^2 / tau0
/// with the discrete kernel but 0.645 N^2 / tau0 with the continuous one cut at Nyquist (the
/// sampled spectrum is the continuous one aliased into [0, fs/2]). For white noise the
/// continuous form is still 14 % low at m = 2, 3 % at m = 10 and 1 % at m = 30. For non-integer m
/// the same formula interpolates smoothly.
///
/// The sum: sum_{k = first_bin}^{L/2} psd_k |H_m(f_k)|^2 df (Nyquist bin with weight 1/2),
/// i.e. the band [f_low_hz, rate_hz/2]. The part below f_low_hz, which the Welch PSD does not
/// resolve, is extrapolated with A f^a fitted (least squares on log psd, with the chi-square
/// log bias 1/edf removed) to the bins first_bin .. first_bin * 10^fit_decades and integrated
/// against the exact kernel (quadrature in log f, and the small-f limit
/// |H|^2 -> 2 (pi f tau)^2 analytically below pi f tau = 1e-3). Since |H|^2 ~ f^2 at low f,
/// that integral converges for a > -3 (random walk a = -2 included) and its share grows with
/// tau; a tau is marked valid when that share is <= max_low_fraction (so that the answer
/// does not hinge on the extrapolation) and m <= max_m_fraction * L (the kernel's first lobe,
/// at f ~ 0.37 / tau, then spans >= 3 Welch bins, so the sum resolves it).
/// Preconditions (std::invalid_argument naming the parameter): psd from welch (sizes agree,
/// rate_hz > 0, at least first_bin + 2 bins); every tau finite and >= 1 / rate_hz;
/// options in range. nthreads: parallel over tau, each tau summed by one thread.
AvarPsdResult avar_from_psd(const PsdResult& psd, std::span<const double> tau_s,
                            const AvarPsdOptions& opt = {}, int nthreads = 0);

/// |H_m(f)|^2 of avar_from_psd: 2 sin^4(pi f m tau0) / (m sin(pi f tau0))^2, m = tau_s * rate_hz,
/// for 0 < f <= rate_hz / 2 (its limit 2 (pi f tau)^2 as f -> 0).
double allan_kernel_discrete(double f_hz, double tau_s, double rate_hz);

}  // namespace allanlot::kernels
