// One channel's analysis (docs/statistics.md, docs/fit-and-psd.md): the phase built from the
// samples, every requested Allan-family statistic with its confidence intervals, the eq. (3)
// fit of the overlapping Allan curve, the Welch PSD with its own fit and the eq. (2)
// cross-check. What the results file's channel group holds, computed from the samples alone:
// no file, no thread across channels, no printing (src/workflow/analyze_recording.cpp owns
// those).
#pragma once

#include "src/pipeline/channel_edits.hpp"
#include "src/pipeline/channel_fit.hpp"
#include "src/pipeline/channel_model.hpp"
#include "src/pipeline/channel_powerlaw.hpp"

#include "io/recording.hpp"
#include "io/results.hpp"
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"

#include <memory>
#include <vector>

namespace allanlot::pipeline {

/// The options of `analyze` that change a channel's results (docs/cli.md "Command: analyze").
struct ChannelOptions {
  std::vector<kernels::Stat> stats;  // statistics to compute, in output order
  kernels::TauGridSpec grid;         // which taus
  double confidence = 0.683;         // confidence level of dev_lo / dev_hi, in (0, 1)
  bool fit = true;                   // fit/ (the eq. (3) fit)
  LowpassChoice lowpass;             // the sensor's filter in the fit (analyze --lowpass)
  ModelChoice model;                 // a poor fit modelled as diagnose does (--model-poor-fits)
  bool psd = true;                   // psd/, psd_fit/ and crosscheck/ (Welch PSD, eq. (2))
  kernels::GapPolicy gaps;           // what missing samples become (analyze --gaps)
  int threads = 1;                   // threads inside the kernels (results do not depend on it)
  EditOptions edit;  // drift, outliers, excluded ranges, dynamic deviation (docs/editing.md)
  // Leave a poor fit's model to model_deferred, which analyze runs with every thread once the
  // channels are analysed (the model is most of a poor fit's time; run beside the other
  // channels on one thread, the last one modelled kept one core while the other waited).
  bool defer_model = false;
  // Which noise model: the power-law levels for clocks, eq. (3) for IMU channels (analyze
  // --model; src/pipeline/channel_powerlaw.hpp).
  NoiseModel noise_model = NoiseModel::Auto;
};

/// Seconds one channel spent per stage: kernels (phase, statistics, confidence intervals),
/// psd (PSD, PSD fit, cross-check) and fit (the eq. (3) fit and a poor fit's model).
struct ChannelTimes {
  double kernels = 0, psd = 0, fit = 0;
};

/// What a deferred model needs (ChannelOptions::defer_model): the channel's phase and its
/// overlapping Allan deviation.
struct DeferredModel {
  kernels::PhaseData phase;
  kernels::StatResult oadev;
};

struct ChannelAnalysis {
  io::ChannelResult result;  // status ok, or failed with its reason and what was computed
  ChannelTimes times;
  std::shared_ptr<DeferredModel> deferred;  // a poor fit's model still to make (defer_model)
  bool ok() const { return result.status.is_ok(); }
};

/// The channel's description in the results (path, units, rate, length, data type), status
/// "ok" and nothing computed yet: what a channel that cannot even be read is recorded with.
io::ChannelResult describe_channel(const io::ChannelInfo& channel);

/// Analyses one channel from its samples as read (`samples` is consumed: it is freed once the
/// phase is built, and the phase once the PSD's rate is built, so that a channel holds at most
/// two arrays of its length at any stage). Never throws: a numerical precondition (a record too
/// short for any tau, samples whose differences overflow) fails the channel with the reason in
/// its status; a statistic that cannot run on gaps, or a record too short for a PSD, is a note.
ChannelAnalysis analyze_channel(const io::ChannelInfo& channel,
                                kernels::LargeVector<double> samples, const ChannelOptions& opt);

/// Makes a deferred model (a.deferred, then freed) with `threads` kernel threads: the same
/// result as analyze_channel without defer_model. Never throws, as analyze_channel.
void model_deferred(ChannelAnalysis& a, const ChannelOptions& opt, int threads);

}  // namespace allanlot::pipeline
