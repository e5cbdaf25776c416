// The equation (3) fit of one channel's overlapping Allan curve, turned into the results
// file's fit/ record (channel and datasheet units), and the paper-style table of a unit.
#pragma once

#include "io/results.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/model/units.hpp"
#include "kernels/simulate/lowpass.hpp"
#include "kernels/spectral/psd.hpp"

#include <array>

#include <string>
#include <vector>

namespace allanlot::pipeline {

/// How the eq. (3) fit treats the sensor's own anti-alias and decimation filter (analyze
/// --lowpass, docs/fit-and-psd.md "The sensor's filter").
struct LowpassChoice {
  enum class Mode {
    Auto,  // named from the curve by diagnose's lowpass test (kernels::find_lowpass)
    None,  // no filter: every tau is fitted
    Given  // `filter`, as the option gave it
  };
  Mode mode = Mode::Auto;
  kernels::Lowpass filter;  // Mode::Given
};

/// Fits eq. (3) to `oadev` (with edf filled by add_confidence) of a channel of `n_samples` rate
/// samples (one fewer than its phase points) at interval `tau0_s`, in channel units `units`. When
/// the curve has more taus than the fit needs (--taus all), it is fitted on a log-spaced subset of
/// at most 16 taus per decade, which carries the same information (neighbouring overlapping
/// estimates are correlated above 0.9) at a fraction of the cost of the covariance model;
/// adev_model is given on every oadev tau. A filter (named by `lowpass` or found on the curve)
/// leaves the taus it biases out of the fit: the fit starts at kernels::lowpass_first_m, and the
/// record says the filter, the first tau fitted and the chi2/dof of the fit over all taus. Uses
/// reusable kernels::Eq3Fit objects per thread. `terms_out`, when given, receives the fitted
/// terms (for the comparison with the PSD fit). `threads`: OpenMP threads of a new curve
/// shape's covariance model (the same result for any).
io::FitRecord fit_channel(const kernels::StatResult& oadev, double tau0_s, std::int64_t n_samples,
                          const std::string& units, const LowpassChoice& lowpass = {},
                          std::array<kernels::TermFit, kernels::kNumTerms>* terms_out = nullptr,
                          int threads = 1);

/// One term of a fit as the results file records it: the value, sigma and 95 % upper bound
/// in channel units (`units`) and converted to datasheet units (kernels/model/units.hpp).
io::TermRecord term_record(kernels::units::Term t, const kernels::TermFit& f,
                           const std::string& units);

/// "auto", "none", "cutoff_hz=X" or "taps=X" as a LowpassChoice (the filter checked against
/// rate_hz when given, else only for its own range); throws std::invalid_argument naming the
/// text.
LowpassChoice parse_lowpass_choice(const std::string& text);

/// Fits the same five terms to the channel's Welch PSD (kernels::psd_fit) for psd_fit/, with
/// f and psd_model on the binned frequencies; when `allan_terms` is given (the fit/ terms of
/// the same channel), adds the term-by-term comparison (kernels::compare_fits): z_vs_fit,
/// max_abs_z, worst_term and agree. `threads`: OpenMP threads of new regressors (the same
/// result for any).
io::FitRecord psd_fit_channel(const kernels::PsdResult& psd, const std::string& units,
                              const std::array<kernels::TermFit, kernels::kNumTerms>* allan_terms,
                              int threads = 1);

/// The fitted coefficients of every channel of a unit in datasheet units, laid out as the
/// paper's Table: one block per sensor family, one row per term, one column per channel;
/// "v ± s" for detected terms, "< u" (95 % upper bound) for the others. With `si`, in SI
/// units instead (kernels::units::to_si: rad/s or m/s^2 and seconds, analyze --si).
std::string fit_table(const io::RecordingResult& r, bool si = false);

/// Rows of cells as terminal lines, indented by two spaces, columns aligned by UTF-8 code
/// points (not bytes: "±" is one column), two spaces apart.
std::string aligned_rows(const std::vector<std::vector<std::string>>& rows);

}  // namespace allanlot::pipeline
