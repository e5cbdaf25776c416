// A channel's data editing before its phase is built (docs/editing.md): time ranges excluded,
// outliers removed, a drift model fitted and removed, each recorded in the channel's results
// (edits/, drift/); and, on the samples as analysed, the dynamic Allan deviation (dynamic/).
// The recording itself is never changed: the edits act on the samples in memory.
#pragma once

#include "io/recording.hpp"
#include "io/results.hpp"
#include "kernels/allan/dynamic.hpp"
#include "kernels/common/large_vector.hpp"
#include "kernels/drift/drift.hpp"
#include "kernels/edit/edit.hpp"

#include <span>
#include <vector>

namespace allanlot::pipeline {

/// The options of `analyze` that edit a channel (docs/cli.md `--drift`, `--outliers`,
/// `--exclude`, `--dynamic`). The defaults edit nothing.
struct EditOptions {
  kernels::DriftModel drift = kernels::DriftModel::None;  // none, linear, quadratic, log, diffusion
  double outlier_sigmas = 0;                              // > 0: the robust rule's k; 0 = off
  std::vector<kernels::TimeRange> exclude;                // time ranges to exclude, s
  kernels::DynamicSpec dynamic;                           // the dynamic deviation; off by default
};

/// Excludes opt.exclude, removes the outliers, then fits and removes the drift, in place on
/// `samples` (as read, after the quality screen), recording r.edits, r.drift and a note. Throws
/// std::invalid_argument for a drift model that cannot be fitted (too few samples).
void edit_channel(io::ChannelResult& r, const io::ChannelInfo& channel,
                  kernels::LargeVector<double>& samples, const EditOptions& opt);

/// r.dynamic from `samples` as analysed (edited, gaps filled) when opt.dynamic is on; a window
/// longer than the record, or too many windows, is a note rather than a failure.
void dynamic_channel(io::ChannelResult& r, const io::ChannelInfo& channel,
                     std::span<const double> samples, const EditOptions& opt, int threads);

}  // namespace allanlot::pipeline
