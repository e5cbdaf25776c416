// The equation (3) fit of one channel's overlapping Allan curve, turned into the results
// file's fit/ record (channel and datasheet units), and the paper-style table of a unit.
#pragma once

#include "io/results.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/spectral/psd.hpp"

#include <array>

#include <string>
#include <vector>

namespace allanlot::pipeline {

/// Fits eq. (3) to `oadev` (with edf filled by add_confidence) of a channel of `n_samples` rate
/// samples (one fewer than its phase points) at interval `tau0_s`, in channel units `units`. When
/// the curve has more taus than the fit needs (--taus all), it is fitted on a log-spaced subset of
/// at most 16 taus per decade, which carries the same information (neighbouring overlapping
/// estimates are correlated above 0.9) at a fraction of the cost of the covariance model;
/// adev_model is given on every oadev tau. Uses one reusable kernels::Eq3Fit per thread.
/// `terms_out`, when given, receives the fitted terms (for the comparison with the PSD fit).
/// `threads`: OpenMP threads of a new curve shape's covariance model (the same result for any).
io::FitRecord fit_channel(const kernels::StatResult& oadev, double tau0_s, std::int64_t n_samples,
                          const std::string& units,
                          std::array<kernels::TermFit, kernels::kNumTerms>* terms_out = nullptr,
                          int threads = 1);

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
/// "v ± s" for detected terms, "< u" (95 % upper bound) for the others.
std::string fit_table(const io::RecordingResult& r);

/// Rows of cells as terminal lines, indented by two spaces, columns aligned by UTF-8 code
/// points (not bytes: "±" is one column), two spaces apart.
std::string aligned_rows(const std::vector<std::vector<std::string>>& rows);

}  // namespace allanlot::pipeline
