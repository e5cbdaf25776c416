// A channel that eq. (3) alone does not describe (a poor fit), modelled as `allanlot diagnose`
// models it: eq. (3) plus the effects the data name (the sensor's filter, resonances,
// Gauss-Markov humps, bias jumps, lines), so that the coefficients reported, judged against a
// spec and compared across the lot are those of a model that fits (docs/fit-and-psd.md "When
// eq. (3) is a poor fit").
#pragma once

#include "io/results.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"

#include <cstdint>

namespace allanlot::pipeline {

/// analyze --model-poor-fits: what the modelling of a poor fit uses (docs/cli.md).
struct ModelChoice {
  bool enabled = true;  // auto: model every poor fit; off: keep eq. (3) alone
  // Monte Carlo replicas of the verdict (kernels::DiagnoseOptions::mc_replicas): 19, the fewest
  // with which the replicas' p95 has its level (kernels/diagnose/lot_noise.hpp) and with which
  // diagnose runs its verdict's round; `allanlot diagnose` uses 30.
  int replicas = 19;
  std::uint64_t seed = 7;  // seed of the replicas (diagnose's default)
};

/// When result.fit is a poor fit (kernels::FitStatus::PoorFit) and `choice` is enabled: runs
/// kernels::diagnose on the channel's rate (rebuilt from `phase`) against the eq. (3) fit over
/// every tau (and a filter --lowpass gave, and the output's rounding when the samples lie on
/// one step), fits the structure it names again on `oadev` (kernels::fit_to_curve), and
/// replaces fit/'s terms, adev_model (on `oadev`'s taus) and the read-outs' model by that
/// model's, with the model's description, diagnose's gap and verdict and the effects
/// (fit/model*, fit/effects/). A record diagnose cannot model
/// (too short, or any other exception of diagnose) keeps its eq. (3) fit, with a note saying
/// why. Threads: diagnose's (results do not depend on them).
void model_poor_fit(io::ChannelResult& result, const kernels::PhaseData& phase,
                    const kernels::StatResult& oadev, const ModelChoice& choice, int threads);

}  // namespace allanlot::pipeline
