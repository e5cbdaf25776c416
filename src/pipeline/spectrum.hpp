// The frequency-domain stage of one channel (docs/fit-and-psd.md): the Welch PSD of the
// channel's rate (psd/), the eq. (3) terms fitted to it (psd_fit/) and equation (2) applied to
// it at the oadev taus against the time-domain variance (crosscheck/).
#pragma once

#include "io/results.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/spectral/psd.hpp"

#include <array>
#include <vector>

namespace allanlot::pipeline {

/// The rate rebuilt from the phase: (x[k+1] - x[k]) rate_hz, so mean-removed, and NaN where
/// the increment is missing (a gap), so that phase and rate input are treated alike.
kernels::LargeVector<double> rate_from_phase(const kernels::PhaseData& phase);

/// The crosscheck/ record: eq. (2)'s Allan variance from the PSD (`from_psd`, at the taus of
/// `oadev`) against the time-domain one, their ratio, and the tau where |log10 ratio| is
/// largest over the valid taus with a finite positive ratio (max_abs_log10_ratio and worst_tau,
/// both NaN when there is none).
io::CrosscheckRecord crosscheck_record(const kernels::StatResult& oadev,
                                       const kernels::AvarPsdResult& from_psd);

/// Fills psd/, psd_fit/ and crosscheck/ of `result` from the channel's phase, which it releases
/// once the rate is built (this is the channel's last stage). `allan_terms`, when given, are
/// the fit/ terms the PSD fit is compared with. A record too short for a PSD is a note in
/// result.notes, not a failure.
void add_spectrum(io::ChannelResult& result, kernels::PhaseData& phase,
                  const kernels::StatResult& oadev, int threads,
                  const std::array<kernels::TermFit, kernels::kNumTerms>* allan_terms);

}  // namespace allanlot::pipeline
