// A channel's phase under the gap policy (docs/statistics.md "Gaps"): the short runs of missing
// samples filled (kernels/allan/gaps.hpp), the account of what was done in the channel's
// results and its notes.
#pragma once

#include "io/recording.hpp"
#include "io/results.hpp"
#include "kernels/allan/gaps.hpp"
#include "kernels/common/large_vector.hpp"

namespace allanlot::pipeline {

/// The phase of `samples` (filled in place under `policy`), with r.n_gaps (missing samples as
/// read), and, on a channel with gaps, r.gap_policy, r.n_filled, r.filled_runs, r.gap_runs_left
/// and a note saying what was filled and what was left. Throws std::invalid_argument as
/// kernels::make_phase does.
kernels::PhaseData channel_phase(io::ChannelResult& r, const io::ChannelInfo& channel,
                                 kernels::LargeVector<double>& samples,
                                 const kernels::GapPolicy& policy, int nthreads);

}  // namespace allanlot::pipeline
