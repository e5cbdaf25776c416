// The eq. (3) fit of a record of rate samples, as `plan --verify` and `watch` make it: the
// overlapping Allan variance on 16 log-spaced taus per decade (the grid `analyze` fits), the
// Greenhall-Riley edf of each tau from the identified noise (kernels/uncertainty), and the fit
// with its sandwich covariance (kernels/model/fit.hpp).
#pragma once

#include "kernels/model/fit.hpp"

#include "kernels/simulate/simulate.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace allanlot::kernels {

/// The log grid's density of the fits made here: 16 taus per decade, as `analyze`.
inline constexpr int kPlanTausPerDecade = 16;

/// The overlapping Allan deviation of `rate` (samples at rate_hz) on the plan grid, with its
/// edf (kernels::add_confidence). Throws std::invalid_argument when the record spans fewer than
/// 3 octaves of tau (33 samples).
StatResult record_curve(std::span<const double> rate, double rate_hz, int threads = 1);

/// Fits eq. (3) to the overlapping Allan variance of `rate` (samples at rate_hz). `fitter`
/// keeps the covariance basis of the last curve shape, so records of one length share it.
/// Throws std::invalid_argument when the record spans fewer than 3 octaves of tau (33 samples).
FitResult fit_record(std::span<const double> rate, double rate_hz, Eq3Fit& fitter, int threads = 1);

/// The fits of `replicas` independent records of n_samples simulated from `spec`, replica r
/// drawn from the Philox stream (seed, r): the check of a planned length (`plan --verify`).
std::vector<FitResult> simulated_fits(const ChannelSpec& spec, std::int64_t n_samples, int replicas,
                                      std::uint64_t seed, int threads = 1);

}  // namespace allanlot::kernels
