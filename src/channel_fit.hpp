// The equation (3) fit of one channel's overlapping Allan curve, turned into the results
// file's fit/ record (channel and datasheet units), and the paper-style table of a unit.
#pragma once

#include "io/results.hpp"
#include "kernels/phase.hpp"
#include "kernels/stats.hpp"

#include <string>

namespace allanlot::cli {

/// Fits eq. (3) to `oadev` (with edf filled by add_confidence) of a channel with phase data
/// `p` and channel units `units`. When the curve has more taus than the fit needs (--taus
/// all), it is fitted on a log-spaced subset of at most 16 taus per decade, which carries the
/// same information (neighbouring overlapping estimates are correlated above 0.9) at a
/// fraction of the cost of the covariance model; adev_model is given on every oadev tau.
/// Uses one reusable kernels::Eq3Fit per thread.
io::FitRecord fit_channel(const kernels::StatResult& oadev, const kernels::PhaseData& p,
                          const std::string& units);

/// The fitted coefficients of every channel of a unit in datasheet units, laid out as the
/// paper's Table: one block per sensor family, one row per term, one column per channel;
/// "v ± s" for detected terms, "< u" (95 % upper bound) for the others.
std::string fit_table(const io::RecordingResult& r);

}  // namespace allanlot::cli
